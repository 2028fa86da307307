#!/usr/bin/python3
"""Work-precision plots, measured orders, the headline table and the targets, from
bench/work_precision's CSV (ours) and bench/peers/peer_work_precision's (the peers, with our default
integrator timed in the same run as rigid_<integrator>).

    /usr/bin/python3 bench/report/plot_work_precision.py [RESULTS_DIR]      (Debian's python3-matplotlib)

Writes RESULTS_DIR/wp_<case>.png, headline.csv and orders.csv, and prints the report's Markdown
section (bench/report/write_report.py includes it in REPORT.md).
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from report_common import (add_footer, fmt, fnum, md_table, read_meta,  # noqa: E402
                           read_rows)

DEFAULT = "hybrid4"  # the project's default integrator (physics/integrator.cpp)
# Our integrators: theory order, and whether the scheme has the gyroscopic term (without it, it
# converges to the wrong motion for unequal principal moments: no order to measure there).
OURS = {"hybrid4": (4, True), "exact_rotor4": (4, True), "exact_rotor": (2, True), "rk4": (4, True), "dlm": (2, True),
        "implicit_gyro": (1, True), "games103": (1, False), "notes_explicit_euler": (1, False),
        "notes_midpoint": (2, False), "notes_leapfrog": (2, False)}
OUR_STYLE = {"hybrid4": ("crimson", "o", 2.8), "exact_rotor4": ("firebrick", "h", 2.2), "exact_rotor": ("darkorange", "s", 1.8),
             "rk4": ("black", "^", 1.6), "dlm": ("deeppink", "v", 1.4),
             "implicit_gyro": ("saddlebrown", "D", 1.2), "games103": ("dimgray", "x", 1.0),
             "notes_explicit_euler": ("gray", "+", 0.8), "notes_midpoint": ("darkgray", "1", 0.8),
             "notes_leapfrog": ("silver", "2", 0.8)}
# Peers: nominal order by mode (from the integrator each mode runs), and one colour family each.
PEER_ORDER = {"mujoco_euler": 1, "mujoco_rk4": 4, "mujoco_implicit": 1}
PEER_CMAP = {"mujoco": "Blues", "bullet": "Greens", "ode": "Purples"}
SMOOTH_CASES_NOTE = "every case is a smooth ODE; none has contacts or switches"
SATURATION = 0.3    # errors above this (rad or m) are outside the asymptotic range
ROUND_OFF = 1e-10   # errors below this are round-off: nothing left to measure
FLOOR = 1e-16       # errors drawn at least at this height (exact to round-off)
METRICS = [("err_orientation_rad", "orientation error (rad)"),
           ("err_angular_velocity", "angular velocity error (rad/s)"),
           ("err_position_m", "position error (m)"),
           ("energy_drift_rel", "worst relative energy drift"),
           ("momentum_drift_rel", "worst relative angular momentum drift")]


def scored_column(rows):
    """The error a case is scored on: orientation, or (stiff drag) the worst position error."""
    return "err_orientation_rad" if any(math.isfinite(fnum(r["err_orientation_rad"]))
                                        for r in rows) else "err_position_m"


def peer_nominal(name):
    base = name.replace("_site", "").replace("_callback", "").replace("_damping", "")
    return PEER_ORDER.get(base, 1)


def theory_of(name):
    return OURS[name][0] if name in OURS else peer_nominal(name)


def applies(name, case_rows):
    """Whether a method's order is defined on a case: a scheme without the gyroscopic term only
    converges where the body is isotropic (the stiff drag case)."""
    consistent = OURS.get(name, (0, "nogyro" not in name))[1]
    return consistent or case_rows[0]["case"] == "stiff_drag"


def measured_order(points, theory):
    """(order, note). The slope of log(error) against log(dt) over the finest steps of the
    asymptotic range: errors below SATURATION, above ROUND_OFF, and, when the error stops falling
    at the finest steps (the last refinement of dt gains less than half the theory's order), more
    than 100x that floor (its smallest error). Fitted on the three finest such steps, contiguous
    in the sweep."""
    pts = sorted(((dt, e) for dt, e in points if math.isfinite(e) and e > 0), reverse=True)
    if not pts:
        return None, "blows up"
    if max(e for _, e in pts) < ROUND_OFF:
        return "exact", "round-off at every step"
    floor = 0.0
    if len(pts) >= 2:
        (dt0, e0), (dt1, e1) = pts[-2], pts[-1]
        if math.log(e0 / e1) / math.log(dt0 / dt1) < 0.5 * theory:
            floor = min(e for _, e in pts)
    fit = []  # the contiguous run of finest steps inside the range
    for dt, e in reversed(pts):
        if max(ROUND_OFF, 100 * floor) < e < SATURATION:
            fit.insert(0, (dt, e))
        elif fit:
            break
    fit = fit[-3:]
    if len(fit) < 2:
        return None, "error does not fall with dt" if floor else "too few steps in range"
    xs = [math.log(dt) for dt, _ in fit]
    ys = [math.log(e) for _, e in fit]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    steps = f"1/{round(1 / fit[0][0])} to 1/{round(1 / fit[-1][0])} s"
    return slope, f"fit on {len(fit)} steps, {steps}"


def curves(rows, column):
    """{integrator: [(dt, cost per simulated s, error, ns per body-step)]} in CSV order."""
    out = {}
    for r in rows:
        out.setdefault(r["integrator"], []).append(
            (fnum(r["dt"]), fnum(r["cpu_ns_per_sim_second"]), fnum(r[column]),
             fnum(r["ns_per_body_step"])))
    return out


def peer_colours(names):
    colours = {}
    for engine, cmap in PEER_CMAP.items():
        modes = [n for n in names if n.startswith(engine + "_")]
        for i, n in enumerate(modes):
            colours[n] = plt.get_cmap(cmap)(0.45 + 0.5 * i / max(1, len(modes) - 1))
    return colours


def draw(ax, name, pts, style, dashed, label):
    color, marker, width = style
    finite = [(c, max(e, FLOOR)) for _, c, e, _ in pts if math.isfinite(e)]
    if finite:  # the default on top of everything
        ax.loglog([c for c, _ in finite], [e for _, e in finite], linestyle="--" if dashed else "-",
                  marker=marker, color=color, linewidth=width, markersize=4,
                  markerfacecolor="none" if dashed else color, label=label,
                  zorder=3 if name == DEFAULT else 2)
    for dt, c, e, _ in pts:
        if math.isinf(e):  # blew up: an X at the top of the panel, at the cost of its run
            ax.plot([c], [1], marker="X", color=color, markersize=8, clip_on=False,
                    transform=ax.get_xaxis_transform())
        elif abs(dt - 1e-3) < 1e-12 and math.isfinite(e):
            ax.plot([c], [max(e, FLOOR)], marker="o", markersize=11, markerfacecolor="none",
                    markeredgecolor=color)


def legend_label(name, rows):
    """The method and its measured order on this case (theory in brackets)."""
    text, _ = order_cell(name, rows)
    text = text.split(" (")[0].replace(" ✗", "")
    return f"{name}: p = {text} ({theory_of(name)})"


def plot_case(case, ours_rows, peer_rows, meta, outdir):
    scored = scored_column(ours_rows or peer_rows)
    panels = [scored] + [m for m, _ in METRICS if m != scored and any(
        fnum(r[m]) > 0 for r in ours_rows + peer_rows if math.isfinite(fnum(r[m])))]
    labels = dict(METRICS)
    fig = plt.figure(figsize=(15, 10))
    grid = fig.add_gridspec(2, max(2, len(panels) - 1), height_ratios=[2.2, 1])
    axes = [fig.add_subplot(grid[0, :])] + [fig.add_subplot(grid[1, i])
                                            for i in range(len(panels) - 1)]
    peer_names = list(dict.fromkeys(r["integrator"] for r in peer_rows
                                    if not r["integrator"].startswith("rigid_")))
    colours = peer_colours(peer_names)
    for ax, column in zip(axes, panels):
        for name, pts in curves(ours_rows, column).items():
            draw(ax, name, pts, OUR_STYLE.get(name, ("black", ".", 1)), False,
                 legend_label(name, ours_rows))
        for name, pts in curves(peer_rows, column).items():
            if name in colours:
                draw(ax, name, pts, (colours[name], "o", 1.2), True, legend_label(name, peer_rows))
        ax.set_ylabel(labels[column], fontsize=9 if ax is axes[0] else 7)
        ax.grid(True, which="major", alpha=0.3)
        ax.tick_params(labelsize=7)
    axes[0].set_xlabel("CPU time per simulated second per body (ns)")
    axes[0].set_title(f"{case}: error against cost. Ours solid, peers dashed (MuJoCo blue, "
                      "Bullet green, ODE purple); circled: dt = 1 ms; X at the top: blew up; "
                      "p: measured order (theory)", fontsize=10)
    axes[0].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    add_footer(fig, meta, "cost: thread CPU time, median of repeats; ours and peers from "
               "separate runs here (the headline's ratios come from one run)")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(os.path.join(outdir, f"wp_{case}.png"), dpi=90)
    plt.close(fig)


def at_1ms(rows, name):
    for r in rows:
        if r["integrator"] == name and abs(fnum(r["dt"]) - 1e-3) < 1e-12:
            return r
    return None


def headline(case, peer_rows):
    """Our default against the best peer mode (lowest scored error) at dt = 1 ms, both from
    the peers' run, where their costs were timed interleaved."""
    column = scored_column(peer_rows)
    ours = at_1ms(peer_rows, "rigid_" + DEFAULT)
    candidates = [r for r in peer_rows if abs(fnum(r["dt"]) - 1e-3) < 1e-12
                  and not r["integrator"].startswith("rigid_") and math.isfinite(fnum(r[column]))]
    if not ours or not candidates:
        return None
    best = min(candidates, key=lambda r: (fnum(r[column]), fnum(r["ns_per_body_step"])))
    e_ours, e_peer = fnum(ours[column]), fnum(best[column])
    c_ours, c_peer = fnum(ours["ns_per_body_step"]), fnum(best["ns_per_body_step"])
    err_ratio = e_peer / max(e_ours, FLOOR)
    cost_ratio = c_ours / c_peer
    return {"case": case, "scored_on": column, "ours_error": e_ours,
            "best_peer": best["integrator"], "peer_error": e_peer, "error_ratio": err_ratio,
            "ours_ns": c_ours, "peer_ns": c_peer, "cost_ratio": cost_ratio,
            "error_pass": err_ratio >= 1000, "cost_pass": cost_ratio <= 0.2}


def below_check(peer_rows, ours_names=None):
    """Target 2 on one case, from the peers' run: every peer run (cost c, error e) must be beaten
    by a run of ours costing at most c (error below e). `ours_names`: which of our methods in that
    run count (default: our default integrator alone; "all": every rigid_* curve of the run, i.e.
    their lower envelope). Returns (beaten, total, misses), misses as one line per peer mode."""
    column = scored_column(peer_rows)
    cv = curves(peer_rows, column)
    if ours_names == "all":
        ours_names = [n[len("rigid_"):] for n in cv if n.startswith("rigid_")]
    ours = [(c, e) for n in (ours_names or [DEFAULT]) for _, c, e, _ in cv.get("rigid_" + n, [])]
    beaten, total, misses = 0, 0, []
    for name, pts in cv.items():
        if name.startswith("rigid_"):
            continue
        cheaper, worse = [], []
        for dt, c, e, _ in pts:
            total += 1
            within = [oe for oc, oe in ours if oc <= c]
            if within and min(within) < e:  # an infinite e (blow-up) is beaten by any finite run
                beaten += 1
            elif not within:
                cheaper.append(f"1/{round(1 / dt)}")
            else:
                worse.append(f"1/{round(1 / dt)} s ({fmt(e)} against ours {fmt(min(within))})")
        if cheaper:
            misses.append(f"{name} at {', '.join(cheaper)} s: cheaper than our cheapest run")
        if worse:
            misses.append(f"{name} at " + ", ".join(worse))
    return beaten, total, misses


def ours_in_run(peer_rows):
    """Our methods that ran alongside the peers (rows rigid_<integrator>), default first."""
    names = list(dict.fromkeys(r["integrator"][len("rigid_"):] for r in peer_rows
                               if r["integrator"].startswith("rigid_")))
    return sorted(names, key=lambda n: n != DEFAULT)


def engine_best(case_rows, engine, column):
    """'mode: error, cost' of an engine's most accurate mode at dt = 1 ms on one case; for
    "rigid", our default's (the column is headed by it, and the peers' run has our others too)."""
    prefix = "rigid_" + DEFAULT if engine == "rigid" else engine + "_"
    rows = [r for r in case_rows if (r["integrator"] == prefix if engine == "rigid"
                                     else r["integrator"].startswith(prefix))
            and abs(fnum(r["dt"]) - 1e-3) < 1e-12 and math.isfinite(fnum(r[column]))]
    if not rows:
        return "-"
    r = min(rows, key=lambda r: fnum(r[column]))
    figures = f"{fmt(fnum(r[column]))}, {fmt(fnum(r['ns_per_body_step']))} ns"
    return figures if engine == "rigid" else f"{r['integrator'][len(engine) + 1:]}: {figures}"


def order_cell(name, case_rows):
    """(text, verdict) for the orders table; verdict None when it does not count."""
    if not applies(name, case_rows):
        return "n/a", None
    column = scored_column(case_rows)
    theory = theory_of(name)
    pts = [(fnum(r["dt"]), fnum(r[column])) for r in case_rows if r["integrator"] == name]
    order, note = measured_order(pts, theory)
    if order is None:
        return f"n/m ({note})", None
    if order == "exact":
        return "exact", True
    ok = abs(order - theory) <= 0.3
    return f"{order:.2f}" + ("" if ok else " ✗"), ok


def headline_table(heads, outdir):
    keys = ["case", "scored_on", "ours_error", "best_peer", "peer_error", "error_ratio",
            "ours_ns", "peer_ns", "cost_ratio", "error_pass", "cost_pass"]
    with open(os.path.join(outdir, "headline.csv"), "w") as f:
        f.write(",".join(keys) + "\n")
        for h in heads:
            f.write(",".join(str(h[k]) for k in keys) + "\n")
    rows = [[h["case"], fmt(h["ours_error"]), h["best_peer"], fmt(h["peer_error"]),
             fmt(h["error_ratio"]) + ("" if h["error_pass"] else " ✗"), fmt(h["ours_ns"]),
             fmt(h["peer_ns"]), f"{h['cost_ratio']:.3f}" + ("" if h["cost_pass"] else " ✗"),
             "pass" if h["error_pass"] and h["cost_pass"] else "**fail**"] for h in heads]
    return md_table(["case", f"ours ({DEFAULT}) error", "best peer mode", "its error",
                     "error ratio peer/ours (>= 1000)", "ours ns/body-step", "peer ns/body-step",
                     "cost ratio ours/peer (<= 0.2)", "target 1"], rows)


def orders(names, by_case, outdir):
    """The orders table (Markdown and orders.csv): ours from their own sweep, the peers from
    theirs. Returns (markdown, verdicts [(name, case, ok)], unmeasured [(name, case)])."""
    cases = list(by_case)
    table, verdicts, unmeasured = [], [], []
    with open(os.path.join(outdir, "orders.csv"), "w") as f:
        f.write("integrator,theory," + ",".join(cases) + "\n")
        for name in names:
            cells = []
            for c in cases:
                rows = by_case[c][0] if name in OURS else by_case[c][1]
                if not any(r["integrator"] == name for r in rows):
                    cells.append("")
                    continue
                text, ok = order_cell(name, rows)
                cells.append(text)
                if name in OURS and ok is not None:
                    verdicts.append((name, c, ok))
                elif name in OURS and text.startswith("n/m"):
                    unmeasured.append((name, c))
            f.write(f"{name},{theory_of(name)}," + ",".join(x.replace(",", ";") for x in cells)
                    + "\n")
            table.append([f"**{name}**" if name in OURS else name, str(theory_of(name))] + cells)
    return md_table(["method", "theory / nominal"] + cases, table), verdicts, unmeasured


def case_table(ours_rows, peer_rows, column):
    """Every method on one case: its error and cost at dt = 1 ms, and where it blew up."""
    table = []
    methods = list(curves(ours_rows, column).items()) + [
        (n, v) for n, v in curves(peer_rows, column).items() if not n.startswith("rigid_")]
    for name, pts in methods:
        one = [x for x in pts if abs(x[0] - 1e-3) < 1e-12]
        blew = [f"1/{round(1 / dt)}" for dt, _, e, _ in pts if math.isinf(e)]
        table.append([name, fmt(one[0][2]) if one else "-", fmt(one[0][3]) if one else "-",
                      ", ".join(blew) if blew else "-"])
    return md_table(["method", "error at dt = 1 ms", "ns per body-step", "blew up at dt (s)"],
                    table)


def section(outdir):
    """Draws the plots and returns the report's pieces: tables (Markdown) and verdicts."""
    ours_all = read_rows(os.path.join(outdir, "work_precision.csv"))
    peers_all = read_rows(os.path.join(outdir, "peers.csv"))
    meta = read_meta(os.path.join(outdir, "work_precision.csv.meta"))
    cases = list(dict.fromkeys(r["case"] for r in ours_all + peers_all))
    by_case = {c: ([r for r in ours_all if r["case"] == c],
                   [r for r in peers_all if r["case"] == c]) for c in cases}
    for case, (o, p) in by_case.items():
        plot_case(case, o, p, meta, outdir)
    with_peers = [c for c in cases if by_case[c][1]]

    heads = [h for h in (headline(c, by_case[c][1]) for c in with_peers) if h]
    side = [[c] + [engine_best(by_case[c][1], e, scored_column(by_case[c][1]))
                   for e in ("rigid", "mujoco", "bullet", "ode")] for c in with_peers]
    below = {c: below_check(by_case[c][1], "all") for c in with_peers}
    below_default = {c: below_check(by_case[c][1]) for c in with_peers}
    ours_run = list(dict.fromkeys(n for c in with_peers for n in ours_in_run(by_case[c][1])))
    names = list(dict.fromkeys(r["integrator"] for r in ours_all)) + list(dict.fromkeys(
        r["integrator"] for r in peers_all if not r["integrator"].startswith("rigid_")))
    orders_md, verdicts, unmeasured = orders(names, by_case, outdir)
    per_case = []
    for c in cases:
        o, p = by_case[c]
        column = scored_column(o or p)
        per_case.append((c, column, (o or p)[0]["reference"], case_table(o, p, column)))
    return {
        "meta": meta, "peers_meta": read_meta(os.path.join(outdir, "peers.csv.meta")),
        "headline": heads, "headline_md": headline_table(heads, outdir),
        "side_by_side_md": md_table(["case", f"ours ({DEFAULT})", "MuJoCo's best mode",
                                     "Bullet's best mode", "ODE's best mode"], side),
        "below": below, "below_default": below_default, "ours_in_run": ours_run,
        "below_md": md_table(
            ["case", "peer runs beaten by a cheaper-or-equal run of ours (any of ours)",
             "not beaten", f"beaten by {DEFAULT} alone", f"not beaten by {DEFAULT} alone"],
            [[c, f"{b} of {t}", "; ".join(m) if m else "-",
              f"{below_default[c][0]} of {below_default[c][1]}",
              "; ".join(below_default[c][2]) if below_default[c][2] else "-"]
             for c, (b, t, m) in below.items()]),
        "orders_md": orders_md, "orders_verdicts": verdicts, "orders_unmeasured": unmeasured,
        "per_case": per_case}


def main():
    outdir = sys.argv[1] if len(sys.argv) > 1 else "bench/results"
    s = section(outdir)
    print(s["headline_md"], "\n\n", s["below_md"], "\n\n", s["orders_md"])
    for case, column, ref, table in s["per_case"]:
        print(f"\n## {case} (scored on {column}; reference: {ref})\n\n{table}")


if __name__ == "__main__":
    main()
