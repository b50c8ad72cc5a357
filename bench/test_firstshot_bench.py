"""The harness's own maths (bench/firstshot_bench.py): ctest runs it as bench_harness_selftest.

Standard library only; nothing here runs the tools.
"""
import math
import os
import tempfile
import types
import unittest

import firstshot_bench as fb

NAN = float("nan")


def curve(times, errors, mare_factor=0.5):
    """A median curve as summarize() returns it."""
    return [{"budget": t, "n": 1, "total": t, "render": t, "preprocess": 0.0, "spp": 1.0, "rel_rmse": e,
             "mare": e * mare_factor, "nrmse": NAN} for t, e in zip(times, errors)]


BUDGETS = [1, 2, 4, 8, 16, 32, 64, 128]


def mc_curve(c, budgets=BUDGETS, offset=0.0, floor=0.0):
    """Unbiased Monte Carlo after a fixed cost: e = c / sqrt(t - offset), plus a bias floor in quadrature."""
    times = [b + offset for b in budgets]
    return curve(times, [math.hypot(c / math.sqrt(b), floor) for b in budgets])


class TimeToReach(unittest.TestCase):
    def test_power_law_crossing_is_exact(self):
        # e = 0.8 t^-1/2 is a straight line in log-log: the interpolated crossing is exact.
        times = [0.5, 1, 2, 4, 8]
        errors = [0.8 / math.sqrt(t) for t in times]
        t, kind = fb.time_to_reach(times, errors, 0.4)
        self.assertEqual(kind, "interpolated")
        self.assertAlmostEqual(t, 4.0, places=9)
        t, kind = fb.time_to_reach(times, errors, 0.5)
        self.assertAlmostEqual(t, (0.8 / 0.5) ** 2, places=9)

    def test_unsorted_input(self):
        times = [8, 0.5, 2, 1, 4]
        errors = [0.8 / math.sqrt(t) for t in times]
        t, _ = fb.time_to_reach(times, errors, 0.3)
        self.assertAlmostEqual(t, (0.8 / 0.3) ** 2, places=9)

    def test_first_point_already_below(self):
        t, kind = fb.time_to_reach([1, 2], [0.05, 0.04], 0.1)
        self.assertEqual((t, kind), (1, "at_or_before"))

    def test_never_reached(self):
        t, kind = fb.time_to_reach([1, 2, 4], [0.5, 0.4, 0.35], 0.1)
        self.assertEqual(kind, "not_reached")
        self.assertTrue(math.isnan(t))

    def test_first_crossing_of_a_noisy_curve(self):
        # Down through the target between 2 and 4 s, back above at 8 s: the first crossing counts.
        t, kind = fb.time_to_reach([1, 2, 4, 8], [0.4, 0.2, 0.05, 0.12], 0.1)
        self.assertEqual(kind, "interpolated")
        self.assertAlmostEqual(t, 2 * 2 ** 0.5, places=9)  # halfway in log e between 0.2 and 0.05

    def test_ignores_non_positive_and_nan(self):
        t, kind = fb.time_to_reach([0, 1, float("nan"), 4], [1, 0.2, 0.1, 0.05], 0.1)
        self.assertEqual(kind, "interpolated")
        self.assertAlmostEqual(t, 2.0, places=9)  # between (1, 0.2) and (4, 0.05)


class Targets(unittest.TestCase):
    def test_target_info_on_a_monte_carlo_curve(self):
        c = mc_curve(0.4)  # e = 0.4/sqrt(t): 5% at 64 s, 2% at 400 s (past the longest budget)
        i5 = fb.target_info(c, 0.05)
        self.assertEqual(i5["kind"], "interpolated")
        self.assertAlmostEqual(i5["time"], 64.0, places=6)
        i2 = fb.target_info(c, 0.02)
        self.assertEqual(i2["kind"], "not_reached")
        self.assertEqual((i2["t_max"], i2["best_error_time"]), (128, 128))
        self.assertAlmostEqual(i2["best_error"], 0.4 / math.sqrt(128))
        self.assertAlmostEqual(fb.target_info(c, 0.05, "mare")["time"], 16.0, places=6)  # MARE = e/2
        self.assertIsNone(fb.target_info([], 0.05))
        self.assertIn("not reached (best 0.0354 at 128 s)", fb.describe_ttt(i2))

    def test_multiple_targets_are_ordered(self):
        c = mc_curve(0.2)
        times = [fb.target_info(c, t)["time"] for t in (0.1, 0.05, 0.02)]
        for got, want in zip(times, (4.0, 16.0, 100.0)):
            self.assertAlmostEqual(got, want, places=6)

    def test_a_bias_floor_is_never_reached(self):
        # First-shot's own bias: a floor above the target stops the curve however long it runs.
        c = mc_curve(0.1, floor=0.025)
        self.assertEqual(fb.target_info(c, 0.02)["kind"], "not_reached")
        self.assertEqual(fb.target_info(c, 0.05)["kind"], "interpolated")

    def test_best_of_takes_the_smallest_time(self):
        infos = {"path": fb.target_info(mc_curve(0.4), 0.05),       # 64 s
                 "path-tree": fb.target_info(mc_curve(0.2), 0.05),  # 16 s
                 "slow": fb.target_info(mc_curve(1.0), 0.05)}       # not reached, longest run 128 s
        b = fb.best_of(infos)
        self.assertEqual((b["method"], b["kind"]), ("path-tree", "interpolated"))
        self.assertAlmostEqual(b["time"], 16.0, places=6)

    def test_best_of_is_an_upper_bound_when_an_unfinished_method_stopped_earlier(self):
        # A method that timed out after 4 s might have reached the target before 16 s.
        infos = {"a": fb.target_info(mc_curve(0.2), 0.05), "b": fb.target_info(mc_curve(1.0, budgets=[1, 2, 4]), 0.05)}
        self.assertEqual(fb.best_of(infos)["kind"], "at_or_before")

    def test_best_of_is_an_upper_bound_beside_a_method_below_the_target_at_once(self):
        # 'a' crosses at 1.1 s; 'b' was below at its first point (1.5 s) and may have been there much sooner.
        infos = {"a": {"time": 1.1, "kind": "interpolated", "t_max": 8},
                 "b": {"time": 1.5, "kind": "at_or_before", "t_max": 8}}
        b = fb.best_of(infos)
        self.assertEqual((b["method"], b["time"], b["kind"]), ("a", 1.1, "at_or_before"))
        self.assertEqual(fb.describe_best(b), "≤ 1.1 s (a)")

    def test_best_of_when_none_reaches_it(self):
        infos = {"a": fb.target_info(mc_curve(1.0), 0.05), "b": fb.target_info(mc_curve(1.0, budgets=[1, 2, 4, 8]), 0.05)}
        b = fb.best_of(infos)
        self.assertEqual((b["method"], b["kind"], b["t_max"]), (None, "not_reached", 8))
        self.assertIn("not reached (> 8 s)", fb.describe_best(b))
        self.assertIsNone(fb.best_of({}))
        self.assertIsNone(fb.best_of({"x": None}))

    def test_scene_targets_best_baseline_ratio(self):
        # Baselines 'path' (5% at 64 s) and 'path-tree' (5% at 16 s): the baseline is path-tree. First-shot
        # reaches 5% at 1 s of render after 0.5 s of preprocessing (total 1.5 s): ratio 16/1.5... interpolated.
        curves = {"path": mc_curve(0.4), "path-tree": mc_curve(0.2), "path+firstshot": mc_curve(0.05, offset=0.5),
                  "irradiance-cache": mc_curve(0.01)}  # 'other': fastest, but not a baseline
        roles = {"path": "baseline", "path-tree": "baseline", "path+firstshot": "firstshot",
                 "irradiance-cache": "other"}
        st = fb.scene_targets(curves, roles, [0.05, 0.02])
        e5 = st[("rel_rmse", 0.05)]
        self.assertEqual(e5["baseline"]["method"], "path-tree")
        self.assertEqual(e5["firstshot"]["method"], "path+firstshot")
        self.assertEqual(e5["firstshot"]["kind"], "at_or_before")  # 0.05 at its first point (1.5 s)
        value, rel = e5["ratio"]
        self.assertEqual(rel, "≥")
        self.assertAlmostEqual(value, 16.0 / 1.5, places=6)
        e2 = st[("rel_rmse", 0.02)]
        self.assertEqual(e2["baseline"]["method"], "path-tree")  # 100 s
        ft = e2["firstshot"]["time"]  # 0.05/sqrt(b) = 0.02 at b = 6.25 s, + 0.5 s, interpolated in log-log
        self.assertTrue(6.25 < ft < 7.5, ft)
        value, rel = e2["ratio"]
        self.assertEqual(rel, "=")
        self.assertAlmostEqual(value, 100.0 / ft, places=6)
        self.assertEqual(fb.format_ratio(value, rel), f"{100.0 / ft:.2f}×")
        self.assertIn(("mare", 0.02), st)

    def test_no_baseline_or_no_firstshot(self):
        st = fb.scene_targets({"path": mc_curve(0.2)}, {"path": "baseline"}, [0.05])
        self.assertIsNone(st[("rel_rmse", 0.05)]["firstshot"])
        self.assertEqual(fb.format_ratio(*st[("rel_rmse", 0.05)]["ratio"]), "–")


class Ratios(unittest.TestCase):
    def test_speedup_bounds(self):
        self.assertEqual(fb.speedup((4.0, "interpolated", 8), (1.0, "interpolated")), "4.00×")
        self.assertEqual(fb.speedup((4.0, "interpolated", 8), (1.0, "at_or_before")), "≥ 4.00×")
        self.assertEqual(fb.speedup((1.0, "at_or_before", 8), (0.5, "interpolated")), "≤ 2.00×")
        self.assertEqual(fb.speedup((math.nan, "not_reached", 8), (2.0, "interpolated")), "> 4.0×")
        self.assertEqual(fb.speedup((4.0, "interpolated", 8), (math.nan, "not_reached")), "–")
        self.assertEqual(fb.speedup((1.0, "at_or_before", 8), (0.5, "at_or_before")), "–")

    def test_first_shot_that_never_gets_there_is_slower(self):
        # The baseline reaches it at 4 s; first-shot did not within 16 s: the ratio is below 4/16.
        self.assertEqual(fb.ratio((4.0, "interpolated", 8), (NAN, "not_reached", 16.0)), (0.25, "<"))
        self.assertEqual(fb.speedup((4.0, "interpolated", 8), (NAN, "not_reached", 16.0)), "< 0.2×")
        self.assertEqual(fb.ratio((NAN, "not_reached", 8), (NAN, "not_reached", 16.0))[1], None)

    def test_goal_checks(self):
        self.assertEqual(fb.goal_check(12.0, "=", 10), "met")
        self.assertEqual(fb.goal_check(8.0, "=", 10), "not met")
        self.assertEqual(fb.goal_check(12.0, ">", 10), "met")
        self.assertEqual(fb.goal_check(8.0, ">", 10), "open")  # a lower bound below the goal
        self.assertEqual(fb.goal_check(8.0, "≤", 10), "not met")
        self.assertEqual(fb.goal_check(12.0, "≤", 10), "open")
        self.assertEqual(fb.goal_check(0.5, "<", 1), "not met")
        self.assertEqual(fb.goal_check(NAN, None, 1), "open")

    def test_goal_status_per_scene(self):
        # many-lights: 10x at the smallest target only.
        text, verdict = fb.goal_status("many-lights", {0.05: (3.0, "="), 0.02: (11.0, "=")})
        self.assertEqual(verdict, "met")
        self.assertIn("2%", text)
        self.assertEqual(fb.goal_status("many-lights", {0.05: (30.0, "="), 0.02: (9.0, "=")})[1], "not met")
        # cornell: never slower, at every target.
        self.assertEqual(fb.goal_status("cornell", {0.05: (1.2, "="), 0.02: (0.9, "=")})[1], "not met")
        self.assertEqual(fb.goal_status("cornell", {0.05: (1.2, "="), 0.02: (1.5, ">")})[1], "met")
        self.assertEqual(fb.goal_status("cornell", {0.05: (1.2, "="), 0.02: (NAN, None)})[1], "open")
        self.assertEqual(fb.goal_status("sierpinski-glossy", {0.02: (2.0, "=")}), ("–", None))
        for scene in ("many-lights", "fixture-room", "office-floor"):
            self.assertEqual(fb.GOALS[scene]["min_ratio"], 10.0)


class Reference(unittest.TestCase):
    def test_goal_is_a_third_of_the_smallest_target(self):
        self.assertAlmostEqual(fb.reference_goal([0.05, 0.02], 1 / 3), 0.02 / 3)

    def test_next_round(self):
        self.assertEqual(fb.next_reference_round(512, 0.004, 0.0067, 100, 3600), ("converged", 0))
        self.assertEqual(fb.next_reference_round(512, 0.02, 0.0067, 100, 3600), ("render", 512))  # doubles
        self.assertEqual(fb.next_reference_round(512, 0.02, 0.0067, 1900, 3600), ("time_limit", 0))
        self.assertEqual(fb.next_reference_round(512, NAN, 0.0067, 100, 3600), ("render", 512))
        with self.assertRaises(ValueError):
            fb.next_reference_round(0, NAN, 0.0067, 0, 3600)

    def simulate(self, start_half, noise_at_1spp, seconds_per_spp, goal, max_seconds):
        """The ensure_reference loop with noise = c/sqrt(spp) and a constant rate: (spp per half, seconds, action)."""
        half = start_half
        seconds = 2 * half * seconds_per_spp
        rounds = 1
        while True:
            noise = noise_at_1spp / math.sqrt(2 * half)
            action, add = fb.next_reference_round(half, noise, goal, seconds, max_seconds)
            if action != "render":
                return half, seconds, action, rounds
            seconds += 2 * add * seconds_per_spp
            half += add
            rounds += 1

    def test_converges_to_the_first_power_of_two_past_the_need(self):
        # noise 1.0 at 1 spp, goal 0.02/3: needs 22500 spp; from 2 x 512, doubling reaches 32768.
        half, seconds, action, rounds = self.simulate(512, 1.0, 0.01, 0.02 / 3, 3600)
        self.assertEqual((action, 2 * half, rounds), ("converged", 32768, 6))
        self.assertAlmostEqual(seconds, 327.68)
        self.assertGreaterEqual(2 * half, fb.predicted_spp(1024, 1.0 / math.sqrt(1024), 0.02 / 3))

    def test_stops_before_passing_the_time_limit(self):
        half, seconds, action, _ = self.simulate(512, 1.0, 0.2, 0.02 / 3, 3600)
        self.assertEqual(action, "time_limit")
        self.assertLessEqual(seconds, 3600)
        self.assertGreater(2 * seconds, 3600)  # one more doubling would have passed it
        # The first round is always rendered, even when it alone is past the limit.
        self.assertEqual(self.simulate(512, 1.0, 10, 0.02 / 3, 60)[2:], ("time_limit", 1))

    def test_seeds_never_repeat(self):
        seeds = [s for r in range(20) for s in fb.reference_seeds(1000, r)]
        self.assertEqual(len(seeds), len(set(seeds)))
        self.assertEqual(fb.reference_seeds(1000, 0), (1000, 1001))

    def test_key_changes_with_scene_bytes_and_settings(self):
        with tempfile.TemporaryDirectory() as d:
            scene, renderer = os.path.join(d, "s.json"), os.path.join(d, "render")
            for p, text in ((scene, "{}"), (renderer, "binary")):
                with open(p, "w") as f:
                    f.write(text)
            path, tree = fb.method_spec("path"), fb.method_spec("path-tree")
            k0 = fb.reference_key(scene, renderer, "path", path, 512, 1000, 160, 120)
            self.assertEqual(k0, fb.reference_key(scene, renderer, "path", path, 512, 1000, 160, 120))
            self.assertNotEqual(k0, fb.reference_key(scene, renderer, "path-tree", tree, 512, 1000, 160, 120))
            self.assertNotEqual(k0, fb.reference_key(scene, renderer, "path", path, 256, 1000, 160, 120))
            self.assertNotEqual(k0, fb.reference_key(scene, renderer, "path", path, 512, 1001, 160, 120))
            self.assertNotEqual(k0, fb.reference_key(scene, renderer, "path", path, 512, 1000, 80, 60))
            self.assertEqual(k0["args"], ["--light-sampler", "all"])
            with open(scene, "w") as f:
                f.write("{ }")
            self.assertNotEqual(k0, fb.reference_key(scene, renderer, "path", path, 512, 1000, 160, 120))
            self.assertEqual(k0["scene_sha256"], "44136fa355b3678a1146ad16f7e8649e94fb4fc21fe77e8310c060f61caaff8a")

    def test_load_reference_needs_matching_key_and_files(self):
        with tempfile.TemporaryDirectory() as d:
            info = {"key": {"k": 1}, "files": {"mean": "m.exr"}}
            fb.write_reference_json(d, dict(info, seconds=1.0), 0.01, 60, types.SimpleNamespace(ref_noise_fraction=1 / 3,
                                                                                                 threads=2), "converged")
            self.assertIsNone(fb.load_reference(d, {"k": 1}))  # m.exr missing
            open(os.path.join(d, "m.exr"), "w").close()
            self.assertEqual(fb.load_reference(d, {"k": 1})["status"], "converged")
            self.assertIsNone(fb.load_reference(d, {"k": 2}))


class Summaries(unittest.TestCase):
    def test_median_skips_missing(self):
        self.assertEqual(fb.median([3, None, 1, float("nan"), 2]), 2)
        self.assertTrue(math.isnan(fb.median([None])))

    def test_slope_of_a_power_law(self):
        times = [0.5, 1, 2, 4, 8]
        self.assertAlmostEqual(fb.loglog_slope(times, [3 * t ** -0.5 for t in times]), -0.5, places=12)
        self.assertTrue(math.isnan(fb.loglog_slope([1], [1])))

    def test_summarize_takes_medians_per_budget(self):
        rows = []
        for rep, (t, e) in enumerate([(1.0, 0.3), (1.2, 0.1), (1.1, 0.2)]):
            rows.append({"method": "path", "budget_s": "1", "status": "ok", "total_s": str(t), "render_wall_s": str(t),
                         "preprocess_wall_s": "0", "spp": "10", "rel_rmse": str(e), "mare": str(e / 2), "nrmse": ""})
        rows.append({"method": "path", "budget_s": "1", "status": "timeout", "total_s": "99", "rel_rmse": ""})
        curves = fb.summarize({"methods": ["path", "other"], "rows": rows})
        self.assertEqual(list(curves), ["path"])
        (p,) = curves["path"]
        self.assertEqual((p["n"], p["total"], p["rel_rmse"], p["mare"]), (3, 1.1, 0.2, 0.1))
        self.assertTrue(math.isnan(p["nrmse"]))

    def test_tables_and_summary_are_written(self):
        ref = {"key": {"width": 160, "height": 120, "method": "path", "integrator": "path",
                       "args": ["--light-sampler", "all"]},
               "spp": 32768, "seconds": 300.0, "noise_rel_rmse": 0.005, "noise_mare": 0.003,
               "noise_goal_rel_rmse": 0.0067, "status": "converged"}
        curves = {"path": mc_curve(0.4), "path-tree": mc_curve(0.2), "path+firstshot": mc_curve(0.05, offset=0.5)}
        roles = {"path": "baseline", "path-tree": "baseline", "path+firstshot": "firstshot"}
        rows = [{"method": m, "rep": "0", "status": "ok", "threads": "2", "load_avg_1m": "1.0"} for m in curves]
        result = {"scene": "many-lights", "rows": rows, "methods": list(curves), "roles": roles,
                  "about": {m: fb.method_spec(m).about for m in curves}, "notes": ["x: skipped"], "ref": ref,
                  "targets": [0.05, 0.02]}
        with tempfile.TemporaryDirectory() as d:
            table = fb.write_table(result, curves, os.path.join(d, "t.md"))
            self.assertIn("| **best baseline** |", table)
            self.assertIn("100 s (path-tree)", table)
            self.assertIn("rel. RMSE 5% | rel. RMSE 2% | MARE 5% | MARE 2%", table)
            self.assertIn("Goal (rel. RMSE): ≥ 10× at 2%: met.", table)
            args = types.SimpleNamespace(width=160, height=120, threads=2, reps=3, baselines=["path", "path-tree"])
            summary = fb.write_summary([(result, curves)], [0.05, 0.02], os.path.join(d, "summary.md"), args)
            self.assertTrue(os.path.exists(os.path.join(d, "summary.md")))
            row = next(line for line in summary.splitlines() if line.startswith("| many-lights"))
            cells = [c.strip() for c in row.strip("|").split("|")]
            self.assertEqual(cells[1], "100 s (path-tree)")  # best baseline to 2% comes first
            self.assertTrue(cells[3].endswith("×"))
            self.assertIn("met", cells[7])


class Methods(unittest.TestCase):
    def test_registry(self):
        self.assertEqual([m for m, s in fb.METHODS.items() if s.baseline], ["path", "path-tree"])
        self.assertFalse(any(s.baseline and s.firstshot for s in fb.METHODS.values()))
        path = fb.method_spec("path")
        self.assertEqual((path.integrator, path.args, path.firstshot), ("path", ["--light-sampler", "all"], False))
        self.assertEqual(fb.method_role(path), "baseline")
        self.assertEqual(fb.method_spec("path-tree").args, ["--light-sampler", "tree"])
        fs = fb.method_spec("path+firstshot-patchnee")
        self.assertEqual((fs.integrator, fs.firstshot, fb.method_role(fs)), ("path", True, "firstshot"))
        self.assertIn("--patch-nee", fs.args)
        self.assertEqual(fb.method_role(fb.method_spec("irradiance-cache")), "other")
        self.assertNotIn("--ambient", fb.method_spec("irradiance-cache+firstshot").args)

    def test_unregistered_names(self):
        s = fb.method_spec("irradiance-cache-x+firstshot")
        self.assertEqual((s.integrator, s.firstshot, s.args, s.baseline), ("irradiance-cache-x", True, [], False))
        self.assertEqual(fb.method_spec("foo").integrator, "foo")
        self.assertEqual(fb.split_method("path+firstshot"), ("path", True))

    def test_overrides_and_appends(self):
        over, app = fb.parse_method_args(["path=", "irradiance-cache+firstshot+=--accuracy 0.2",
                                          "foo=--bar 1"])
        self.assertEqual(over, {"path": [], "foo": ["--bar", "1"]})
        self.assertEqual(app, {"irradiance-cache+firstshot": ["--accuracy", "0.2"]})
        self.assertEqual(fb.method_spec("path", over, app).args, [])
        self.assertEqual(fb.method_spec("irradiance-cache+firstshot", over, app).args[-2:], ["--accuracy", "0.2"])
        self.assertEqual(fb.method_spec("foo+firstshot", over, app).args, ["--bar", "1"])  # an integrator's
        self.assertEqual(fb.method_spec("irradiance-cache", over, app).args, fb.METHODS["irradiance-cache"].args)

    def test_baselines_option(self):
        self.assertTrue(fb.method_spec("irradiance-cache", baselines=["irradiance-cache"]).baseline)
        self.assertFalse(fb.method_spec("path", baselines=["path-tree"]).baseline)
        self.assertFalse(fb.method_spec("path+firstshot", baselines=["path+firstshot"]).baseline)  # never both

    def test_parse_method_args_rejects_garbage(self):
        with self.assertRaises(SystemExit):
            fb.parse_method_args(["no-equals-sign"])


class Parsing(unittest.TestCase):
    def test_misc(self):
        self.assertEqual(fb.rotated(["a", "b", "c"], 4), ["b", "c", "a"])
        self.assertEqual(fb.parse_list("1,2,,4"), [1.0, 2.0, 4.0])
        self.assertEqual(fb.fmt_target(0.05), "5%")
        self.assertEqual(fb.fmt_target(0.025), "2.5%")

    def test_tool_summaries(self):
        self.assertEqual(fb.parse_render_summary("160x120 at 64 spp in 1.00 s: 3.59 Mrays/s; 4804 patches"), (64, 1.0))
        self.assertEqual(fb.parse_render_summary("garbage"), (None, None))
        line = "c.fsd: 110 light samples (1 small lights, 0 large), 4804 patches, 349347 non-zero factors, 1.09 s, 100.9 samples/s"
        self.assertEqual(fb.parse_preprocess_summary(line), 1.09)

    def test_scene_names_resolve_to_shipped_files(self):
        name, path = fb.resolve_scene("cornell")
        self.assertEqual((name, os.path.basename(path)), ("cornell", "cornell.json"))
        self.assertIsNone(fb.resolve_scene("no-such-scene-anywhere"))


if __name__ == "__main__":
    unittest.main()
