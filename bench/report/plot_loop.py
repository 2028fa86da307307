#!/usr/bin/python3
"""Loop and network figures from bench/loop_bench's CSVs: rigidd's tick lateness at 1 kHz per body
count and bus (histograms and percentiles, beside the machine's own timer), the wrench-to-state
latency per bus, and the states per second each bus sustains.

    /usr/bin/python3 bench/report/plot_loop.py [RESULTS_DIR]

Reads loop.csv and loop_histogram.csv (loop_bench --csv, --histogram; one row per run and bus,
several runs per configuration), writes loop_lateness.png and prints the report's Markdown section.
Every figure in a table is the median over the runs of that configuration.
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from report_common import add_footer, fmt, fnum, md_table, median, read_meta, read_rows  # noqa

TRANSPORTS = ["dds", "lcm", "both"]
COLOURS = {"dds": "tab:blue", "lcm": "tab:orange", "both": "tab:green", "timer": "gray"}


def med(rows, column):
    return median([fnum(r[column]) for r in rows])


def spread(rows, column):
    v = [fnum(r[column]) for r in rows if not math.isnan(fnum(r[column]))]
    return f" ({fmt(min(v))}-{fmt(max(v))})" if len(v) > 1 else ""


def one_per_run(rows):
    """The loop's own figures appear once per bus of a run: keep one row per run."""
    seen, out = set(), []
    for r in rows:
        if r["run"] not in seen:
            seen.add(r["run"])
            out.append(r)
    return out


def lateness_figure(hist, outdir, meta):
    """One panel per body count: the share of ticks in each lateness bin, per set of buses, and
    the bare timer's (dotted). When rigidd does not log its whole histogram, the per-second
    maxima on both sides instead (the worst tick of each second)."""
    realtime = [h for h in hist if h["mode"] == "realtime"]
    counts = sorted({int(h["bodies"]) for h in realtime})
    if not counts:
        return None
    whole = all(h["source"] == "rigidd_histogram" for h in realtime)
    timer = [h for h in hist if h["mode"] == "timer" and h["spin_us"] == "100" and
             h["source"] == ("timer_samples" if whole else "timer_per_second_max")]
    fig, axes = plt.subplots(1, len(counts), figsize=(max(9, 5 * len(counts)), 4.5), sharey=True,
                             squeeze=False)
    for ax, n in zip(axes[0], counts):
        for transport in TRANSPORTS:
            draw_histogram(ax, [h for h in realtime if int(h["bodies"]) == n
                                and h["transport"] == transport], transport)
        draw_histogram(ax, timer, "timer")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{n:,} bodies, 1 kHz")
        ax.set_xlabel("tick lateness (us)" if whole else "worst tick lateness of a second (us)")
        ax.grid(True, alpha=0.3)
    axes[0][0].set_ylabel("share of ticks" if whole else "share of seconds")
    # One legend for the figure: a panel may lack some buses (quick runs only 1000 bodies on each).
    handles = {}
    for ax in axes[0]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    axes[0][-1].legend(list(handles.values()), list(handles.keys()), fontsize=8, title="buses")
    add_footer(fig, meta, ("every tick of every run" if whole else
                           "rigidd gave no whole histogram: per-second maxima") +
               "; timer = a bare SCHED_FIFO thread, 100 us final spin")
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.savefig(os.path.join(outdir, "loop_lateness.png"), dpi=90)
    plt.close(fig)
    return "rigidd_histogram" if whole else "per_second_max"


def draw_histogram(ax, rows, label):
    """Buckets (low, high, count) summed over runs, regrouped into quarter-octave bins from 16 ns
    (one bin below), drawn as the share of all samples per bin; empty bins left blank."""
    edges = [0.0] + [0.016 * 2 ** (k / 4) for k in range(0, 4 * 20)]
    counts = [0] * (len(edges) - 1)
    for h in rows:
        lo = fnum(h["low_us"])
        k = max(0, min(len(counts) - 1, sum(1 for e in edges[1:] if e <= lo)))
        counts[k] += int(h["count"])
    total = sum(counts)
    if not total:
        return
    last = max(k for k, n in enumerate(counts) if n)
    shares = [n / total if n else math.nan for n in counts[:last + 1]]
    ax.stairs(shares, [max(e, 0.008) for e in edges[:last + 2]], baseline=None,
              color=COLOURS[label], label=label, linestyle=":" if label == "timer" else "-",
              linewidth=1.5)


def section(outdir):
    rows = read_rows(os.path.join(outdir, "loop.csv"))
    if not rows:
        return None
    hist = read_rows(os.path.join(outdir, "loop_histogram.csv"))
    meta = read_meta(os.path.join(outdir, "loop.csv.meta"))
    sources = lateness_figure(hist, outdir, meta)

    timer = [[f"{r['spin_us']} us", fmt(med([r], "lateness_p50_us")),
              fmt(med([r], "lateness_p99_us")), fmt(med([r], "lateness_max_us")),
              r["overruns"]] for r in rows if r["mode"] == "timer"]
    timer_md = md_table(["final spin", "p50 (us)", "p99 (us)", "max (us)",
                         "late by more than a tick"], timer)

    realtime = [r for r in rows if r["mode"] == "realtime"]
    configs = sorted({(int(r["bodies"]), r["transport"]) for r in realtime},
                     key=lambda c: (c[0], TRANSPORTS.index(c[1])))
    loop_rows, latency_rows = [], []
    for n, transport in configs:
        rs = [r for r in realtime if int(r["bodies"]) == n and r["transport"] == transport]
        runs = one_per_run(rs)
        loop_rows.append([f"{n:,}", transport, str(len(runs)), fmt(med(runs, "lateness_p50_us")),
                          fmt(med(runs, "lateness_p99_us")) + spread(runs, "lateness_p99_us"),
                          fmt(med(runs, "lateness_max_us")) + spread(runs, "lateness_max_us"),
                          str(int(sum(fnum(r["overruns"]) for r in runs))),
                          fmt(med(runs, "step_cost_p50_us")), fmt(med(runs, "step_cost_max_us"))])
        for bus in ("dds", "lcm"):
            b = [r for r in rs if r["bus"] == bus]
            if not b:
                continue
            latency_rows.append([f"{n:,}", transport, bus, fmt(med(b, "latency_p50_us")),
                                 fmt(med(b, "latency_p99_us")), fmt(med(b, "latency_max_us")),
                                 str(int(sum(fnum(r["latency_n"]) for r in b))),
                                 str(int(sum(fnum(r["unseen"]) for r in b))),
                                 fmt(med(b, "server_leg_p50_us")), fmt(med(b, "wire_leg_p50_us")),
                                 fmt(med(b, "command_to_state_p50_us"))])
    loop_md = md_table(["bodies", "buses", "runs", "lateness p50 (us)", "p99 (us) (range)",
                        "max (us) (range)", "overruns, all runs", "step cost p50 (us)",
                        "step cost max (us)"], loop_rows)
    latency_md = md_table(["bodies", "buses", "bus", "p50 (us)", "p99 (us)", "max (us)",
                           "pushes seen", "unseen", "of p50: wrench to state published",
                           "state published to received", "rigidd: arrival to state sent p50"],
                          latency_rows)

    fast = [r for r in rows if r["mode"] == "fast"]
    sustain_rows = []
    for n, bus in sorted({(int(r["bodies"]), r["bus"]) for r in fast}):
        rs = [r for r in fast if int(r["bodies"]) == n and r["bus"] == bus]
        got, sent = med(rs, "states_received_per_s"), med(rs, "states_sent_per_s")
        sustain_rows.append([bus, f"{n:,}", str(len(rs)), fmt(got), fmt(got * n),
                             fmt(got * fnum(rs[0]["state_bytes"]) / 1e6), fmt(sent),
                             f"{100 * (1 - got / sent):.0f}%" if sent > 0 else "-"])
    sustain_md = md_table(["bus", "bodies", "runs", "states received per s", "bodies per s",
                           "MB per s (~108 B per body)", "states sent per s", "lost between"],
                          sustain_rows)
    return {"meta": meta, "timer_md": timer_md, "loop_md": loop_md, "latency_md": latency_md,
            "sustain_md": sustain_md, "source": sources}


def main():
    s = section(sys.argv[1] if len(sys.argv) > 1 else "bench/results")
    if s:
        for key in ("timer_md", "loop_md", "latency_md", "sustain_md"):
            print(s[key], "\n")


if __name__ == "__main__":
    main()
