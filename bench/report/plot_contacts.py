#!/usr/bin/python3
"""The contacts section of bench/REPORT.md, from bench/peers/peer_contacts' CSV: the targets for
ours, the engines side by side at the three steps, a table per case, and a plot of error against
cost (contacts.png).

    /usr/bin/python3 bench/report/plot_contacts.py [RESULTS_DIR]      (Debian's python3-matplotlib)

Writes RESULTS_DIR/contacts.png and prints the section's Markdown.
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from report_common import add_footer, fmt, fnum, md_table, read_meta, read_rows  # noqa: E402

STEPS = [1e-3, 1 / 240, 1 / 60]
STEP_NAMES = {1e-3: "1 ms", 1 / 240: "1/240 s", 1 / 60: "1/60 s"}
FLOOR = 1e-16  # errors drawn at least at this height (exact to round-off)
ENGINES = {"rigid": "ours", "mujoco": "MuJoCo", "bullet": "Bullet", "ode": "ODE"}
PEER_CMAP = {"mujoco": "Blues", "bullet": "Greens", "ode": "Purples"}

# The targets on ours: (what, the case and column, the bound, how the rows combine).
TARGETS = [
    ("first and every later impact within 1 us of the closed form, at every dt",
     [("elastic_sphere", "first_impact_error_s"), ("elastic_sphere", "later_impact_error_s"),
      ("bouncing_sphere", "first_impact_error_s"), ("bouncing_sphere", "later_impact_error_s")],
     1e-6, "s"),
    ("penetration at most 1e-9 m (every case, every dt)",
     [(c, "max_penetration_m") for c in ("elastic_sphere", "bouncing_sphere", "resting_cube",
                                          "sliding_cube", "tumbling_cube")], 1e-9, "m"),
    ("elastic apex after 12 bounces within 1e-9 m", [("elastic_sphere", "apex_error_m")], 1e-9,
     "m"),
    ("e = 0.5 rest time within 1 us", [("bouncing_sphere", "rest_time_error_s")], 1e-6, "s"),
    ("sliding stop distance within 1e-9 m", [("sliding_cube", "stop_distance_error_m")], 1e-9,
     "m"),
    ("resting cube moves less than 1e-12 m over 10 s (from t = 1 s)",
     [("resting_cube", "drift_m")], 1e-12, "m"),
]
COST_TARGETS = [("cost per body-step of a sphere bouncing on a plane <= 0.1 us",
                 ["elastic_sphere"], 100.0),
                ("cost per body-step of a box on a plane <= 0.5 us (resting, sliding, tumbling)",
                 ["resting_cube", "sliding_cube", "tumbling_cube"], 500.0)]

# The plot's panels: (case, column, label).
PANELS = [("elastic_sphere", "first_impact_error_s", "elastic sphere: |first impact error| (s)"),
          ("elastic_sphere", "later_impact_error_s",
           "elastic sphere: worst |impact error|, impacts 2-12 (s)"),
          ("elastic_sphere", "max_penetration_m", "elastic sphere: max penetration (m)"),
          ("bouncing_sphere", "rest_time_error_s",
           "e = 0.5 sphere: |rest time error| (s; peers' to a step)"),
          ("sliding_cube", "stop_distance_error_m", "sliding cube: |stop distance error| (m)"),
          ("resting_cube", "drift_m", "resting cube: drift after 1 s (m)")]


def engine_of(mode):
    return mode.split("_", 1)[0]


def step_of(r):
    dt = fnum(r["dt"])
    return min(STEPS, key=lambda s: abs(s - dt))


def value(r, column):
    """|x| of a CSV figure (inf: the run never does it or blew up; NaN: not applicable)."""
    return abs(fnum(r[column]))


def target_check(rows, cases_columns, bound):
    """(worst, ok) over ours' rows: the largest |figure| over the given cases, columns and dt."""
    vals = [value(r, col) for case, col in cases_columns for r in rows
            if r["case"] == case and engine_of(r["engine_mode"]) == "rigid"]
    vals = [v for v in vals if not math.isnan(v)]
    if not vals:
        return None, False
    worst = max(vals)
    return worst, worst <= bound


def falls_through(rows):
    """Whether ours never touched the plane in the drops (a World without a contact stage)."""
    drops = [r for r in rows if engine_of(r["engine_mode"]) == "rigid"
             and r["case"] == "elastic_sphere"]
    return bool(drops) and all(int(fnum(r["impacts"]) or 0) == 0 for r in drops)


def worst_text(worst, unit):
    if worst is None:
        return "-"
    if math.isinf(worst):
        return "never (no impact, never at rest) or blew up"
    return f"{fmt(worst)} {unit}"


def targets_md(rows):
    out = []
    for what, cols, bound, unit in TARGETS:
        worst, ok = target_check(rows, cols, bound)
        out.append([what, worst_text(worst, unit), "PASS" if ok else "**FAIL**"])
    for what, cases, bound in COST_TARGETS:
        ns = [fnum(r["ns_per_body_step"]) for r in rows if r["case"] in cases
              and engine_of(r["engine_mode"]) == "rigid"]
        worst = max(ns) if ns else None
        ok = worst is not None and worst <= bound
        out.append([what, f"{fmt(worst)} ns" if worst is not None else "-",
                    "PASS" if ok else "**FAIL**"])
    ratios = [fnum(r.get("settled_ns_per_body_step")) / fnum(r["free_ns_per_body_step"])
              for r in rows
              if r["case"] == "resting_cube" and engine_of(r["engine_mode"]) == "rigid"]
    ratios = [x for x in ratios if not math.isnan(x)]
    worst = max(ratios) if ratios else None
    ok = worst is not None and worst <= 1.0
    out.append(["a body resting on a plane costs no more than a free body of its model (the "
                "resting cube after 1 s / the same cube falling freely, same run)",
                f"{worst:.2f}x" if worst is not None else "-", "PASS" if ok else "**FAIL**"])
    return md_table(["target (ours)", "ours, worst over the three dt", "verdict"], out)


def cell(rows, case, mode, column, scale=1.0, signed=True):
    """'a / b / c' over the three dt (the figure times scale), '-' where missing."""
    parts = []
    for dt in STEPS:
        r = [x for x in rows if x["case"] == case and x["engine_mode"] == mode and
             abs(step_of(x) - dt) < 1e-12]
        if not r:
            parts.append("-")
            continue
        v = fnum(r[0].get(column))
        if math.isnan(v):
            parts.append("-")
        elif math.isinf(v):
            parts.append("never" if column != "blown_up" else "blows up")
        else:
            x = v * scale
            parts.append((f"{x:+.3g}" if signed else f"{x:.3g}"))
    return " / ".join(parts)


SIDE_BY_SIDE = [
    ("elastic sphere: first impact late by (ms)", "elastic_sphere", "first_impact_error_s", 1e3,
     True),
    ("... worst of impacts 2-12 (ms, absolute)", "elastic_sphere", "later_impact_error_s", 1e3,
     False),
    ("... impacts found (of 12)", "elastic_sphere", "impacts", 1, False),
    ("... max penetration (mm)", "elastic_sphere", "max_penetration_m", 1e3, False),
    ("... energy at the apex after the 12th impact (%)", "elastic_sphere", "energy_error_rel",
     100, True),
    ("e = 0.5 sphere: rest time error (ms)", "bouncing_sphere", "rest_time_error_s", 1e3, True),
    ("sliding cube: stop distance error (mm)", "sliding_cube", "stop_distance_error_m", 1e3, True),
    ("sliding cube: stop time error (ms)", "sliding_cube", "rest_time_error_s", 1e3, True),
    ("resting cube: drift after 1 s (um)", "resting_cube", "drift_m", 1e6, False),
    ("resting cube: max penetration (mm)", "resting_cube", "max_penetration_m", 1e3, False),
    ("tumbling cube: largest energy rise (% of the start's)", "tumbling_cube",
     "max_energy_rise_rel", 100, False),
    ("tumbling cube: at rest after (s)", "tumbling_cube", "rest_time_s", 1, False),
    ("cost per body-step, sphere (us)", "elastic_sphere", "ns_per_body_step", 1e-3, False),
    ("cost per body-step, tumbling cube (us)", "tumbling_cube", "ns_per_body_step", 1e-3, False),
    ("cost per body-step, resting cube after 1 s (us)", "resting_cube", "settled_ns_per_body_step",
     1e-3, False),
    ("cost per body-step, the cube without the plane (us)", "resting_cube",
     "free_ns_per_body_step", 1e-3, False),
]


def side_by_side_md(rows):
    modes = list(dict.fromkeys(r["engine_mode"] for r in rows))
    header = ["figure (1 ms / 1/240 s / 1/60 s)"] + [f"`{m}`" for m in modes]
    table = [[label] + [cell(rows, case, m, col, scale, signed) for m in modes]
             for label, case, col, scale, signed in SIDE_BY_SIDE]
    return md_table(header, table)


CASE_COLUMNS = {
    "elastic_sphere": [("impacts", "impacts (of 12)", 1, "{:.0f}"),
                       ("first_impact_error_s", "first impact (ms)", 1e3, None),
                       ("later_impact_error_s", "worst of 2-12 (ms)", 1e3, None),
                       ("max_penetration_m", "max penetration (mm)", 1e3, None),
                       ("apex_error_m", "apex after 12 (mm)", 1e3, None),
                       ("energy_error_rel", "energy there", 1, None),
                       ("max_energy_rise_rel", "largest energy rise", 1, None)],
    "bouncing_sphere": [("impacts", "impacts", 1, "{:.0f}"),
                        ("exact_impacts", "exact", 1, "{:.0f}"),
                        ("first_impact_error_s", "first impact (ms)", 1e3, None),
                        ("later_impact_error_s", "worst of the others (ms)", 1e3, None),
                        ("max_penetration_m", "max penetration (mm)", 1e3, None),
                        ("apex_error_m", "worst of the first 3 apexes (mm)", 1e3, None),
                        ("rest_rule", "rest rule", None, None),
                        ("rest_time_error_s", "rest time error (ms)", 1e3, None)],
    "resting_cube": [("max_penetration_m", "max penetration (mm)", 1e3, None),
                     ("drift_m", "drift after 1 s (m)", 1, None),
                     ("final_tilt_rad", "final tilt (rad)", 1, None),
                     ("max_energy_rise_rel", "largest energy rise (of m g 1 um)", 1, None),
                     ("max_contact_points", "contact points", 1, "{:.0f}")],
    "sliding_cube": [("rest_rule", "stop rule", None, None),
                     ("rest_time_error_s", "stop time error (ms)", 1e3, None),
                     ("stop_distance_error_m", "stop distance error (mm)", 1e3, None),
                     ("max_penetration_m", "max penetration (mm)", 1e3, None),
                     ("final_tilt_rad", "final tilt (rad)", 1, None)],
    "tumbling_cube": [("max_energy_rise_rel", "largest energy rise (of the start's)", 1, None),
                      ("rest_rule", "rest rule", None, None),
                      ("rest_time_s", "at rest after (s)", 1, None),
                      ("final_tilt_rad", "final tilt (rad)", 1, None),
                      ("max_penetration_m", "max penetration (mm)", 1e3, None)],
}


def case_table(rows, case):
    cols = CASE_COLUMNS[case]
    header = ["engine mode", "dt"] + [h for _, h, _, _ in cols] + [
        "ns / body-step", "after 1 s (ns)", "free body (ns)"]
    table = []
    for r in rows:
        if r["case"] != case:
            continue
        line = [f"`{r['engine_mode']}`", STEP_NAMES[step_of(r)]]
        for col, _, scale, form in cols:
            if scale is None:
                line.append(r[col] or "-")
                continue
            v = fnum(r[col])
            if math.isinf(v):
                line.append("never")
            elif form:
                line.append(form.format(v))
            else:
                line.append(fmt(v * scale))
        if r["blown_up"] == "1":
            line = line[:2] + ["blows up"] * len(cols)
        line += [fmt(fnum(r["ns_per_body_step"])), fmt(fnum(r.get("settled_ns_per_body_step"))),
                 fmt(fnum(r["free_ns_per_body_step"]))]
        table.append(line)
    return md_table(header, table)


def colours(modes):
    out = {}
    for engine, cmap in PEER_CMAP.items():
        ms = [m for m in modes if engine_of(m) == engine]
        for i, m in enumerate(ms):
            out[m] = plt.get_cmap(cmap)(0.5 + 0.45 * i / max(1, len(ms) - 1))
    return out


def plot(rows, meta, outdir):
    modes = list(dict.fromkeys(r["engine_mode"] for r in rows))
    col = colours(modes)
    fig, grid = plt.subplots(2, 3, figsize=(16, 9.5))
    for ax, (case, column, label) in zip(grid.flat, PANELS):
        for m in modes:
            pts = []
            for r in rows:
                if r["case"] != case or r["engine_mode"] != m:
                    continue
                dt = step_of(r)
                pts.append((fnum(r["ns_per_body_step"]) / dt, value(r, column), dt))
            pts.sort()
            ours = engine_of(m) == "rigid"
            color = "crimson" if ours else col.get(m, "gray")
            finite = [(c, max(e, FLOOR)) for c, e, _ in pts if math.isfinite(e)]
            if finite:
                ax.loglog([c for c, _ in finite], [e for _, e in finite],
                          linestyle="-" if ours else "--", marker="o", color=color,
                          linewidth=2.4 if ours else 1.2, markersize=4,
                          markerfacecolor=color if ours else "none", label=m)
            for c, e, dt in pts:
                if math.isinf(e):  # never (or blew up): an X at the top, at the run's cost
                    ax.plot([c], [1], marker="X", color=color, markersize=8, clip_on=False,
                            transform=ax.get_xaxis_transform())
                elif abs(dt - 1e-3) < 1e-12 and math.isfinite(e):
                    ax.plot([c], [max(e, FLOOR)], marker="o", markersize=11,
                            markerfacecolor="none", markeredgecolor=color)
        ax.set_title(label, fontsize=9)
        ax.set_xlabel("CPU time per simulated second per body (ns)", fontsize=8)
        ax.grid(True, which="major", alpha=0.3)
        ax.tick_params(labelsize=7)
    legend = {}
    for ax in grid.flat:
        for h, label in zip(*ax.get_legend_handles_labels()):
            legend.setdefault(label, h)
    labels = [m for m in modes if m in legend]
    handles = [legend[m] for m in labels]
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=8,
               bbox_to_anchor=(0.5, 0.025))
    fig.suptitle("Contacts with a static plane: error against cost, one point per dt (1 ms "
                 "circled, 1/240 s, 1/60 s: the cheaper the coarser); ours solid, peers dashed; "
                 "X at the top: never (lost, never at rest) or blew up; exact drawn at 1e-16",
                 fontsize=10)
    add_footer(fig, meta, "cost: thread CPU time per body-step over dt, median of the "
               "interleaved runs of one process")
    fig.tight_layout(rect=(0, 0.06, 1, 0.96))
    fig.savefig(os.path.join(outdir, "contacts.png"), dpi=90)
    plt.close(fig)


def section(outdir):
    """The report's pieces, or None without contacts.csv."""
    rows = read_rows(os.path.join(outdir, "contacts.csv"))
    if not rows:
        return None
    meta = read_meta(os.path.join(outdir, "contacts.csv.meta"))
    plot(rows, meta, outdir)
    cases = list(dict.fromkeys(r["case"] for r in rows))
    return {"meta": meta, "targets_md": targets_md(rows), "side_md": side_by_side_md(rows),
            "cases": [(c, meta.get("case " + c, ""), case_table(rows, c)) for c in cases],
            "falls_through": falls_through(rows),
            "has_rigid": any(engine_of(r["engine_mode"]) == "rigid" for r in rows)}


def main():
    outdir = sys.argv[1] if len(sys.argv) > 1 else "bench/results"
    s = section(outdir)
    if not s:
        print("no contacts.csv in " + outdir)
        return
    print(s["targets_md"], "\n\n", s["side_md"])
    for case, desc, table in s["cases"]:
        print(f"\n## {case}: {desc}\n\n{table}")


if __name__ == "__main__":
    main()
