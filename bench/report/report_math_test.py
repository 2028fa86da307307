#!/usr/bin/python3
"""The report's arithmetic on made-up sweeps: measured orders (with and without a round-off floor,
non-convergent, exact), the headline's choice of the best peer mode and its ratios, and the check
that our curve lies below every peer's (bench/report/plot_work_precision.py)."""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_contacts as pc  # noqa: E402
import plot_work_precision as wp  # noqa: E402

STEPS = [1 / 60, 1 / 120, 1 / 240, 1 / 500, 1 / 1000, 1 / 2000, 1 / 5000, 1 / 10000]


def sweep(order, scale, floor=0.0):
    return [(dt, scale * dt ** order + floor) for dt in STEPS]


def row(case, integrator, dt, err, ns):
    return {"case": case, "integrator": integrator, "dt": str(dt), "err_orientation_rad": str(err),
            "err_position_m": "0", "ns_per_body_step": str(ns),
            "cpu_ns_per_sim_second": str(ns / dt), "reference": "made up"}


class MeasuredOrder(unittest.TestCase):
    def test_clean_orders(self):
        for p in (1, 2, 4):
            order, _ = wp.measured_order(sweep(p, 10.0 ** p), p)
            self.assertAlmostEqual(order, p, places=6)

    def test_round_off_floor_is_left_out(self):
        order, _ = wp.measured_order(sweep(4, 1e3, floor=1e-9), 4)
        self.assertAlmostEqual(order, 4, delta=0.05)

    def test_no_convergence_is_not_an_order(self):
        order, note = wp.measured_order([(dt, 1e-5 * (1.3 if i % 2 else 1)) for i, dt in
                                         enumerate(STEPS)], 4)
        self.assertIsNone(order)
        self.assertIn("does not fall", note)

    def test_exact(self):
        self.assertEqual(wp.measured_order([(dt, 3e-14) for dt in STEPS], 4)[0], "exact")

    def test_blow_ups_are_skipped(self):
        pts = sweep(1, 10.0)
        pts[0] = (pts[0][0], math.inf)
        self.assertAlmostEqual(wp.measured_order(pts, 1)[0], 1, places=6)


class Headline(unittest.TestCase):
    def rows(self, peer_ns):
        out = []
        for dt in STEPS:
            out.append(row("c", "rigid_" + wp.DEFAULT, dt, 1e-14, 50))
            out.append(row("c", "mujoco_rk4", dt, 7 * dt ** 2, peer_ns))
            out.append(row("c", "ode_gyro", dt, 0.5, 150))
            out.append(row("c", "bullet_gyro_explicit", dt, math.inf if dt > 1 / 200 else 0.4, 300))
        return out

    def test_best_peer_and_ratios(self):
        h = wp.headline("c", self.rows(2000))
        self.assertEqual(h["best_peer"], "mujoco_rk4")
        self.assertAlmostEqual(h["error_ratio"], 7e-6 / 1e-14, delta=1)
        self.assertAlmostEqual(h["cost_ratio"], 50 / 2000)
        self.assertTrue(h["error_pass"] and h["cost_pass"])
        self.assertFalse(wp.headline("c", self.rows(200))["cost_pass"])

    def test_below_every_peer(self):
        beaten, total, misses = wp.below_check(self.rows(2000))
        self.assertEqual((beaten, total), (total, 3 * len(STEPS)))
        self.assertEqual(misses, [])

    def test_a_cheaper_peer_run_is_not_beaten(self):
        rows = [r for r in self.rows(2000) if not (r["integrator"].startswith("rigid_") and
                                                   float(r["dt"]) > 1 / 1000)]
        beaten, total, misses = wp.below_check(rows)
        self.assertLess(beaten, total)
        self.assertTrue(any("cheaper than our cheapest run" in m for m in misses))

    def test_the_envelope_of_ours_counts_when_asked(self):
        # Our default only at fine steps; rk4 alongside, cheap at every step: the default alone
        # misses the peers' cheap runs, the envelope of ours beats them all.
        rows = [r for r in self.rows(2000) if not (r["integrator"].startswith("rigid_") and
                                                   float(r["dt"]) > 1 / 1000)]
        rows += [row("c", "rigid_rk4", dt, 1e-3 * dt ** 4, 20) for dt in STEPS]
        self.assertLess(wp.below_check(rows)[0], wp.below_check(rows)[1])
        beaten, total, misses = wp.below_check(rows, "all")
        self.assertEqual((beaten, total, misses), (total, 3 * len(STEPS), []))
        self.assertEqual(wp.ours_in_run(rows), [wp.DEFAULT, "rk4"])


def contact_rows(engine_mode, **figures):
    """One row per case and step of peer_contacts' CSV, every figure exact unless given."""
    out = []
    for case in ("elastic_sphere", "bouncing_sphere", "resting_cube", "sliding_cube",
                 "tumbling_cube"):
        for dt in pc.STEPS:
            r = {"case": case, "engine_mode": engine_mode, "dt": repr(dt), "impacts": "12",
                 "exact_impacts": "12", "first_impact_error_s": "0",
                 "later_impact_error_s": "1e-13", "max_penetration_m": "0",
                 "apex_error_m": "-2e-15", "energy_error_rel": "0", "max_energy_rise_rel": "0",
                 "rest_rule": "event", "rest_time_error_s": "0", "rest_time_s": "1.2",
                 "stop_distance_error_m": "0", "drift_m": "0", "final_tilt_rad": "0",
                 "max_contact_points": "1", "blown_up": "0", "ns_per_body_step": "40",
                 "settled_ns_per_body_step": "40", "free_ns_per_body_step": "40"}
            r.update({k: v for k, v in figures.items() if not isinstance(v, dict)})
            r.update(figures.get(case, {}))
            out.append(r)
    return out


class ContactTargets(unittest.TestCase):
    def verdicts(self, rows):
        return [line.rsplit("|", 2)[-2].strip() for line in pc.targets_md(rows).splitlines()[2:]]

    def test_exact_and_cheap_passes_every_target(self):
        rows = contact_rows("rigid_hybrid4") + contact_rows("ode_step", first_impact_error_s="1e-4")
        self.assertEqual(set(self.verdicts(rows)), {"PASS"})
        self.assertFalse(pc.falls_through(rows))

    def test_each_bound_fails_past_it(self):
        late = contact_rows("rigid_hybrid4", bouncing_sphere={"later_impact_error_s": "-2e-6"})
        self.assertEqual(self.verdicts(late)[0], "**FAIL**")
        self.assertEqual(self.verdicts(late).count("PASS"), len(self.verdicts(late)) - 1)
        never = contact_rows("rigid_hybrid4", elastic_sphere={"first_impact_error_s": "inf",
                                                              "impacts": "0"})
        self.assertEqual(self.verdicts(never)[0], "**FAIL**")
        self.assertIn("never", pc.targets_md(never))
        self.assertTrue(pc.falls_through(never))
        deep = contact_rows("rigid_hybrid4", tumbling_cube={"max_penetration_m": "2e-9"})
        self.assertEqual(self.verdicts(deep)[1], "**FAIL**")

    def test_costs_and_the_resting_body_against_a_free_one(self):
        sphere = contact_rows("rigid_hybrid4", elastic_sphere={"ns_per_body_step": "101"})
        self.assertEqual(self.verdicts(sphere)[-3:], ["**FAIL**", "PASS", "PASS"])
        box = contact_rows("rigid_hybrid4", sliding_cube={"ns_per_body_step": "501"})
        self.assertEqual(self.verdicts(box)[-3:], ["PASS", "**FAIL**", "PASS"])
        # Resting is judged once settled: the landing's cost does not count.
        landing = contact_rows("rigid_hybrid4", resting_cube={"ns_per_body_step": "44"})
        self.assertEqual(self.verdicts(landing)[-1], "PASS")
        resting = contact_rows("rigid_hybrid4", resting_cube={"settled_ns_per_body_step": "44"})
        self.assertEqual(self.verdicts(resting)[-1], "**FAIL**")
        # The peers' figures never count for ours.
        peer = contact_rows("rigid_hybrid4") + contact_rows("mujoco_rk4", ns_per_body_step="9000")
        self.assertEqual(set(self.verdicts(peer)), {"PASS"})

    def test_side_by_side_cells(self):
        rows = contact_rows("ode_step", elastic_sphere={"first_impact_error_s": "1.47e-4"},
                            bouncing_sphere={"rest_time_error_s": "inf"})
        self.assertEqual(pc.cell(rows, "elastic_sphere", "ode_step", "first_impact_error_s", 1e3),
                         "+0.147 / +0.147 / +0.147")
        self.assertEqual(pc.cell(rows, "bouncing_sphere", "ode_step", "rest_time_error_s", 1e3),
                         "never / never / never")
        self.assertEqual(pc.cell(rows, "sliding_cube", "bullet_tuned", "drift_m", 1), "- / - / -")


if __name__ == "__main__":
    unittest.main()
