"""Unit tests of compare/report/report.py (ctest: report_py_unit): the Pareto front of chart 1,
and one chart drawn from a handful of runs. Run with /usr/bin/python3, as mrr runs the program:
test_report.py MRR, where MRR is the mrr binary whose method table (`mrr methods --json`, the
"methods" a bench's JSON carries) gives the charts their order, colours and markers."""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "compare", "report"))
import report  # noqa: E402

MRR = sys.argv.pop(1) if len(sys.argv) > 1 else os.environ.get("MRR", "mrr")
METHODS = json.loads(subprocess.run([MRR, "methods", "--json"], check=True, capture_output=True, text=True).stdout)
report.use_methods(METHODS)  # what bench_charts does with a bench's JSON; sweep() and the rest read it


def results(runs, stability=()):
    """A bench's JSON around some runs: the table's rows, as `mrr bench` writes them."""
    return {"runs": runs, "stability": list(stability), "devices": {}, "methods": METHODS}


class ParetoFrontTest(unittest.TestCase):
    def test_keeps_the_points_no_other_beats_on_both_axes(self):
        # (RMS, speedup): lower RMS and higher speedup are better.
        points = [(0.01, 2.0), (0.02, 3.0), (0.015, 1.5), (0.03, 2.5), (0.005, 1.2)]
        # (0.015, 1.5) loses to (0.01, 2.0); (0.03, 2.5) loses to (0.02, 3.0).
        self.assertEqual(report.pareto_front(points), [4, 0, 1])

    def test_exact_duplicates_both_stay_and_ties_on_one_axis_drop(self):
        points = [(0.01, 2.0), (0.01, 2.0), (0.01, 1.0), (0.02, 2.0)]
        self.assertEqual(report.pareto_front(points), [0, 1])

    def test_non_finite_points_are_dropped_and_cannot_beat_others(self):
        points = [(0.01, 2.0), (float("nan"), 9.0), (0.0, math.inf), (0.02, 3.0)]
        self.assertEqual(report.pareto_front(points), [0, 3])

    def test_order_is_by_error_then_speedup_descending(self):
        points = [(0.3, 5.0), (0.1, 1.0), (0.2, 4.0)]
        self.assertEqual(report.pareto_front(points), [1, 2, 0])
        self.assertEqual(report.pareto_front([]), [])


class ChartTest(unittest.TestCase):
    def test_sweep_draws_the_papers_figures_beside_ours(self):
        runs = [{"path": "cpu", "scene": "builtin:demo", "method": m, "effect": "ssao", "samples": 64, "width": w,
                 "height": h, "rms": 0.01, "measured_speedup": s, "ideal_speedup": 2 * s}
                for m, s in (("full", 1.0), ("mrr", 1.8)) for w, h in ((320, 180), (640, 360))]
        paper = [{"figure": "fig7", "effect": "ssao", "samples": 64, "width": 1280, "height": 720,
                  "speedup": 1.287, "rms": 0}]
        chart = report.sweep("fig7", "cpu", "ssao", runs, paper, "a test machine")
        # ours at 180 and 360, the paper's at 720: no overlap, so the paper has its own axis
        labels = chart.legend_entries()[1]
        self.assertEqual(labels, ["mrr measured", "mrr ideal (pixels)", "paper, Fig. 7 (GTX 1080, top axis)"])
        self.assertEqual(len(chart.fig.axes), 2)
        paper_line = chart.fig.axes[1].get_lines()[0]
        self.assertEqual(list(paper_line.get_xdata()), [720])
        self.assertIn("(720 to 720) hardly overlap ours (180 to 360)", chart.caption)
        self.assertEqual(paper_line.get_linestyle(), "--")
        self.assertEqual(paper_line.get_markerfacecolor(), "white")  # hollow
        with tempfile.TemporaryDirectory() as folder:
            chart.save(folder)
            self.assertEqual(sorted(os.listdir(folder)), ["fig7-cpu-ssao.png", "fig7-cpu-ssao.svg"])
            with open(os.path.join(folder, "fig7-cpu-ssao.png"), "rb") as f:
                header = f.read(24)
            self.assertEqual(header[:8], b"\x89PNG\r\n\x1a\n")
            self.assertEqual((int.from_bytes(header[16:20], "big"), int.from_bytes(header[20:24], "big")),
                             (report.WIDTH, report.HEIGHT))

    def test_our_points_span_the_axis_whatever_the_papers_heights(self):
        # The --quick bench's heights (54, 90) against the paper's 720 to 2160: before, one axis ran
        # to 2160 and our curves filled its first 4%. Now each curve spans its own axis.
        runs = [{"path": "cpu", "scene": "builtin:demo", "method": m, "effect": "ssao", "samples": 16, "width": w,
                 "height": h, "rms": 0.01, "measured_speedup": s, "ideal_speedup": 2 * s}
                for m, s in (("full", 1.0), ("mrr", 1.2)) for w, h in ((96, 54), (160, 90))]
        paper = [{"figure": "fig7", "effect": "ssao", "samples": 16, "width": 16 * h // 9, "height": h,
                  "speedup": 1.0 + h / 2160, "rms": 0} for h in (720, 1080, 1440, 2160)]
        for figure in ("fig7", "fig9"):
            chart = report.sweep(figure, "cpu", "ssao", runs, [dict(p, figure=figure) for p in paper], "a machine")
            ours, theirs = chart.fig.axes
            lo, hi = ours.get_xlim()
            self.assertGreater((90 - 54) / (hi - lo), 0.8, figure)  # ours fill their axis
            lo, hi = theirs.get_xlim()
            self.assertGreater((2160 - 720) / (hi - lo), 0.8, figure)
        # Where the heights overlap (the docs' bench: 720 to 2160 both), one shared axis, as before.
        same = [dict(r, height={54: 720, 90: 1440}[r["height"]]) for r in runs]
        chart = report.sweep("fig7", "cpu", "ssao", same, paper, "a machine")
        self.assertEqual(len(chart.fig.axes), 1)
        self.assertIn("paper, Fig. 7 (GTX 1080)", chart.legend_entries()[1])
        self.assertTrue(report.shares_axis([720], [720, 2160]))
        self.assertFalse(report.shares_axis([54, 90], [720, 2160]))
        self.assertFalse(report.shares_axis([360, 720], [720, 2160]))  # one point of overlap only
        self.assertTrue(report.shares_axis([720, 1080, 1440], [720, 2160]))

    def test_the_hit_ideal_is_drawn_beside_the_pixel_ideal(self):
        runs = [{"path": "cpu", "scene": "builtin:demo", "method": m, "effect": "ssao", "samples": 64, "width": w,
                 "height": h, "rms": 0.01, "measured_speedup": s, "ideal_speedup": 2 * s, "ideal_speedup_hit": 1.5 * s}
                for m, s in (("full", 1.0), ("mrr", 1.8)) for w, h in ((320, 180), (640, 360))]
        chart = report.sweep("fig7", "cpu", "ssao", runs, [], "a test machine")
        labels = chart.ax.get_legend_handles_labels()[1]
        self.assertEqual(labels, ["mrr measured", "mrr ideal (pixels)", "mrr ideal (pixels on geometry)"])
        self.assertEqual(list(chart.ax.get_lines()[2].get_ydata()), [2.7, 2.7])

    def test_speed_against_flip_is_charted_beside_speed_against_rms(self):
        runs = [{"path": "cpu", "scene": "builtin:demo", "group": "main", "method": m, "effect": "ssao",
                 "samples": 64, "width": 320, "height": 180, "rms": r, "flip": f, "measured_speedup": s}
                for m, r, f, s in (("full", 0.0, 0.0, 1.0), ("mrr", 0.004, 0.009, 1.8), ("uniform-2", 0.02, 0.08, 3.0))]
        names = [c.name for c in report.bench_charts(results(runs), [])]
        self.assertEqual(names, ["speed-vs-rms-cpu-ssao", "speed-vs-flip-cpu-ssao"])
        flip = report.speed_vs_rms("cpu", "ssao", runs, "a test machine", key="flip")
        xs = sorted(x for line in flip.ax.get_lines()[:2] for x in line.get_xdata())
        self.assertEqual(xs, [0.009, 0.08])  # the FLIP means, full left out
        # Bench JSON written before FLIP: the RMS chart alone.
        for r in runs:
            del r["flip"]
        names = [c.name for c in report.bench_charts(results(runs), [])]
        self.assertEqual(names, ["speed-vs-rms-cpu-ssao"])

    def test_flip_flicker_is_charted_beside_flicker(self):
        stability = [{"path": "cpu", "scene": "builtin:demo", "effect": "ssao", "camera_path": k, "frames": 60,
                      "width": 320, "height": 180, "method": m, "flicker": f, "flip_flicker": ff}
                     for k in ("orbit", "dolly") for m, f, ff in (("uniform-2", 0.004, 0.03), ("mrr", 0.001, 0.002))]
        runs = [{"path": "cpu", "group": "none", "effect": "ssao"}]  # the charts go by the runs' paths
        names = [c.name for c in report.bench_charts(results(runs, stability), [])]
        self.assertEqual(names, ["flicker-cpu", "flicker-cpu-flip"])
        chart = report.flicker("cpu", stability, "a test machine", key="flip_flicker")
        heights = sorted(round(b.get_height(), 6) for b in chart.ax.patches)
        self.assertEqual(heights, [0.002, 0.002, 0.03, 0.03])  # the FLIP figures, not the RMS ones
        self.assertEqual(chart.ax.get_ylabel(), "FLIP flicker: mean |FLIP(t) - FLIP(t-1)|")
        # Bench JSON written before FLIP: the RMS flicker chart alone.
        for s in stability:
            del s["flip_flicker"]
        names = [c.name for c in report.bench_charts(results(runs, stability), [])]
        self.assertEqual(names, ["flicker-cpu"])


    def test_mrr_effect_variants_each_get_their_own_colour_on_every_chart(self):
        methods = ("full", "tiles", "mrr-effect", "mrr-effect+c4+p0.15", "mrr-effect+c4+p0.3")
        runs = [{"path": "cpu", "scene": "builtin:demo", "group": "main", "method": m, "effect": e, "samples": 64,
                 "width": 320, "height": 180, "rms": 0.001 * (i + 1), "flip": 0.01, "measured_speedup": 1.0 + i}
                for e in ("ssao", "ssgi") for i, m in enumerate(methods)]
        charts = report.bench_charts(results(runs), [])
        colours = []
        for chart in charts:
            by_label = {line.get_label(): line.get_color() for line in chart.ax.get_lines()}
            colours.append(by_label)
            drawn = [by_label[m] for m in methods[1:]]
            self.assertEqual(len(set(drawn)), len(drawn), by_label)  # no two methods share a colour
            self.assertNotIn("#000000", drawn)  # black is the Pareto front's
        self.assertTrue(all(c == colours[0] for c in colours))  # the same colour on every chart


if __name__ == "__main__":
    unittest.main()
