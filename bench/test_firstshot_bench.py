"""The harness's own maths (bench/firstshot_bench.py): ctest runs it as bench_harness_selftest.

Standard library only; nothing here runs the tools.
"""
import math
import os
import tempfile
import unittest

import firstshot_bench as fb


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


class Summaries(unittest.TestCase):
    def test_median_skips_missing(self):
        self.assertEqual(fb.median([3, None, 1, float("nan"), 2]), 2)
        self.assertTrue(math.isnan(fb.median([None])))

    def test_slope_of_a_power_law(self):
        times = [0.5, 1, 2, 4, 8]
        self.assertAlmostEqual(fb.loglog_slope(times, [3 * t ** -0.5 for t in times]), -0.5, places=12)
        self.assertTrue(math.isnan(fb.loglog_slope([1], [1])))

    def test_speedup_bounds(self):
        self.assertEqual(fb.speedup((4.0, "interpolated", 8), (1.0, "interpolated")), "4.00×")
        self.assertEqual(fb.speedup((4.0, "interpolated", 8), (1.0, "at_or_before")), "≥ 4.00×")
        self.assertEqual(fb.speedup((1.0, "at_or_before", 8), (0.5, "interpolated")), "≤ 2.00×")
        self.assertEqual(fb.speedup((math.nan, "not_reached", 8), (2.0, "interpolated")), "> 4.0×")
        self.assertEqual(fb.speedup((4.0, "interpolated", 8), (math.nan, "not_reached")), "–")

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


class Parsing(unittest.TestCase):
    def test_methods(self):
        self.assertEqual(fb.split_method("path+firstshot"), ("path", True))
        self.assertEqual(fb.split_method("irradiance-cache"), ("irradiance-cache", False))
        self.assertEqual(fb.rotated(["a", "b", "c"], 4), ["b", "c", "a"])

    def test_tool_summaries(self):
        self.assertEqual(fb.parse_render_summary("160x120 at 64 spp in 1.00 s: 3.59 Mrays/s; 4804 patches"), (64, 1.0))
        self.assertEqual(fb.parse_render_summary("garbage"), (None, None))
        line = "c.fsd: 110 light samples (1 small lights, 0 large), 4804 patches, 349347 non-zero factors, 1.09 s, 100.9 samples/s"
        self.assertEqual(fb.parse_preprocess_summary(line), 1.09)

    def test_method_args(self):
        self.assertEqual(fb.parse_method_args(["irradiance-cache=--accuracy 0.2 --bounces 1"]),
                         {"irradiance-cache": ["--accuracy", "0.2", "--bounces", "1"]})


class ReferenceKey(unittest.TestCase):
    def test_changes_with_scene_bytes_and_settings(self):
        with tempfile.TemporaryDirectory() as d:
            scene, renderer = os.path.join(d, "s.json"), os.path.join(d, "render")
            for p, text in ((scene, "{}"), (renderer, "binary")):
                with open(p, "w") as f:
                    f.write(text)
            k0 = fb.reference_key(scene, renderer, 1024, (1, 2), 160, 120)
            self.assertEqual(k0, fb.reference_key(scene, renderer, 1024, (1, 2), 160, 120))
            self.assertNotEqual(k0, fb.reference_key(scene, renderer, 2048, (1, 2), 160, 120))
            self.assertNotEqual(k0, fb.reference_key(scene, renderer, 1024, (1, 3), 160, 120))
            with open(scene, "w") as f:
                f.write("{ }")
            self.assertNotEqual(k0, fb.reference_key(scene, renderer, 1024, (1, 2), 160, 120))
            self.assertEqual(k0["scene_sha256"], "44136fa355b3678a1146ad16f7e8649e94fb4fc21fe77e8310c060f61caaff8a")


if __name__ == "__main__":
    unittest.main()
