#!/usr/bin/python3
"""Throughput plots and tables from bench/throughput's CSV: ns per body-step against the number of
bodies N for each body model and integrator, how the cost grows with N, and memory per body.

    /usr/bin/python3 bench/report/plot_throughput.py [RESULTS_DIR]

Writes RESULTS_DIR/throughput.png and memory.png, and prints the report's Markdown section.
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plot_work_precision import DEFAULT, OUR_STYLE  # noqa: E402
from report_common import add_footer, fmt, fnum, md_table, read_meta, read_rows  # noqa: E402


def series(rows, model, integrator, column="ns_per_body_step"):
    return sorted((int(r["bodies"]), fnum(r[column])) for r in rows
                  if r["model"] == model and r["integrator"] == integrator)


def growth_exponent(pts):
    """b in total time ~ N^b over N >= 100 (1: linear in N; above 1: per-body cost rising)."""
    fit = [(math.log(n), math.log(n * ns)) for n, ns in pts if n >= 100 and ns > 0]
    if len(fit) < 2:
        return math.nan
    mx = sum(x for x, _ in fit) / len(fit)
    my = sum(y for _, y in fit) / len(fit)
    sxx = sum((x - mx) ** 2 for x, _ in fit)
    return sum((x - mx) * (y - my) for x, y in fit) / sxx


def section(outdir):
    rows = read_rows(os.path.join(outdir, "throughput.csv"))
    if not rows:
        return None
    meta = read_meta(os.path.join(outdir, "throughput.csv.meta"))
    models = list(dict.fromkeys(r["model"] for r in rows))
    integrators = list(dict.fromkeys(r["integrator"] for r in rows))

    cols = 3
    nrows = (len(models) + 1 + cols - 1) // cols  # one cell more for the legend
    fig, grid = plt.subplots(nrows, cols, figsize=(14, 4.6 * nrows), sharey=True, squeeze=False)
    axes = list(grid.flat)
    for ax, model in zip(axes, models):
        for name in integrators:
            pts = series(rows, model, name)
            color, marker, width = OUR_STYLE.get(name, ("black", ".", 1.0))
            ax.loglog([n for n, _ in pts], [v for _, v in pts], marker=marker, color=color,
                      linewidth=width, markersize=4, label=name)
        ax.set_title(model, fontsize=10)
        ax.set_xlabel("bodies N")
        ax.grid(True, which="major", alpha=0.3)
    for row in grid:
        row[0].set_ylabel("ns per body-step (CPU time, median)")
    handles, labels = axes[0].get_legend_handles_labels()
    for ax in axes[len(models):]:
        ax.axis("off")
    axes[len(models)].legend(handles, labels, fontsize=9, loc="center")
    add_footer(fig, meta, "one World of N bodies, dt = 1 ms, single thread")
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(os.path.join(outdir, "throughput.png"), dpi=90)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8, 5))
    memory_rows = []
    for model in models:
        heap = series(rows, model, DEFAULT, "heap_bytes_per_body")
        rss = series(rows, model, DEFAULT, "rss_bytes_per_body")
        ax.semilogx([n for n, _ in heap], [v for _, v in heap], marker="o", label=f"{model}: heap")
        nmax, rmax = rss[-1]
        memory_rows.append([model, fmt(heap[-1][1]), fmt(rmax), f"{nmax:,}"])
    ax.set_xlabel("bodies N")
    ax.set_ylabel(f"heap bytes per body a World of N allocates ({DEFAULT})")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    add_footer(fig, meta)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.savefig(os.path.join(outdir, "memory.png"), dpi=90)
    plt.close(fig)

    table = []
    nmax = max(int(r["bodies"]) for r in rows)
    for model in models:
        for name in integrators:
            pts = dict(series(rows, model, name))
            table.append([model, name, fmt(pts.get(1, math.nan)), fmt(pts.get(1000, math.nan)),
                          fmt(pts.get(nmax, math.nan)),
                          fmt(pts.get(nmax, math.nan) / pts.get(1000, math.nan)),
                          fmt(growth_exponent(sorted(pts.items())))])
    return {"meta": meta, "nmax": nmax,
            "table_md": md_table(["model", "integrator", "N = 1", "N = 10^3", f"N = {nmax:,}",
                                  f"cost at {nmax:,} / at 10^3", "exponent b (time ~ N^b)"],
                                 table),
            "memory_md": md_table(["model", f"heap bytes per body at N = {nmax:,}",
                                   "resident bytes per body (build + first step)", "N"],
                                  memory_rows)}


def main():
    s = section(sys.argv[1] if len(sys.argv) > 1 else "bench/results")
    if s:
        print(s["table_md"], "\n\n", s["memory_md"])


if __name__ == "__main__":
    main()
