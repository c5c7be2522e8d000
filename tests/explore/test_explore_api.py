#!/usr/bin/env python3
"""`mrr explore`'s JSON API on its own: status codes, content types, bad inputs
(400 naming the parameter, 404 for unknown layers and paths, path traversal), concurrent
requests, a port in use, and the re-render time at 320x180 SSAO-16. The work budget,
abandoned and superseded renders cancelled, only the server's own Host, and a soak.

    test_explore_api.py path/to/mrr
Without an EGL device the port's checks are skipped unless MRR_REQUIRE_GL=1."""
import http.client
import json
import os
import random
import socket
import threading
import statistics
import subprocess
import sys
import time
import unittest
import urllib.parse
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, __import__("os").path.dirname(__file__))
from explore_server import ExploreServer, port_required  # noqa: E402

MRR = sys.argv.pop(1) if len(sys.argv) > 1 else "build/mrr"
FRAME = "effect=ssao&samples=16&size=320x180"


class ExploreApi(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = ExploreServer(MRR, "--scene", "builtin:demo", "--threads", "2")
        status, cls.info = cls.server.json("api/info")
        assert status == 200, cls.info
        cls.port = cls.info["port"]["available"]

    @classmethod
    def tearDownClass(cls):
        alive = cls.server.alive()
        cls.server.stop()
        assert alive, "the server died during the tests:\n" + "".join(cls.server.stderr_lines)

    def need_port(self):
        if not self.port:
            if port_required():
                self.fail("no port with MRR_REQUIRE_GL=1: " + self.info["port"]["status"])
            self.skipTest("the port is unavailable here: " + self.info["port"]["status"])

    def raw_status(self, path):
        """The status of a request sent exactly as written (no client-side normalisation)."""
        host, port = self.server.url[len("http://"):-1].split(":")
        conn = http.client.HTTPConnection(host, int(port), timeout=60)
        conn.putrequest("GET", path, skip_accept_encoding=True)
        conn.endheaders()
        r = conn.getresponse()
        body = r.read()
        conn.close()
        return r.status, r.getheader("Content-Type", ""), body

    # -- the page and the info --------------------------------------------------------------
    def test_page_and_assets(self):
        for path, ctype in [("", "text/html"), ("explore.js", "text/javascript"), ("explore.css", "text/css")]:
            status, got, body = self.server.get(path)
            self.assertEqual(status, 200, path)
            self.assertTrue(got.startswith(ctype), (path, got))
            self.assertGreater(len(body), 100, path)

    def test_info_lists_scenes_and_teaches_every_stage(self):
        self.assertIn("builtin:demo", self.info["scenes"])
        self.assertFalse(any(s.startswith("/") for s in self.info["scenes"]))
        taught = {step["part"]: step["text"] for step in self.info["teach"]}
        for part in self.info["parts"]:
            self.assertTrue(taught.get(part["name"], "").strip(), "no step-through text for " + part["name"])
        self.assertTrue(taught.get("difference", "").strip())
        self.assertTrue(taught.get("flip", "").strip())

    # -- frames, layers, probes -------------------------------------------------------------
    def test_frame_report(self):
        status, ctype, body = self.server.get("api/frame?" + FRAME)
        self.assertEqual(status, 200)
        self.assertTrue(ctype.startswith("application/json"))
        report = json.loads(body)
        self.assertEqual((report["width"], report["height"], report["samples"]), (320, 180, 16))
        self.assertEqual(len(report["levels"]), 4)
        self.assertGreater(report["ideal_speedup"], 1.0)
        # explore opens on the method: the rule is off, and the report says what it would decide
        self.assertNotIn("never_slower", report)
        would = report["explore"]["rule_off"]
        self.assertIsInstance(would["would_fall_back"], bool)
        self.assertGreater(would["predicted_full_ms"], 0.0)
        self.assertGreater(would["predicted_mrr_ms"], 0.0)
        self.assertIn("error_vs_full", report)
        self.assertGreater(report["explore"]["measured_speedup"], 0.0)
        self.assertIn("stencil.L0", report["explore"]["layers"])
        # with the rule on, it decides and the report says how
        status, _, body = self.server.get("api/frame?" + FRAME + "&never_slower=on")
        self.assertEqual(status, 200)
        on = json.loads(body)
        self.assertIn("never_slower", on)
        self.assertNotIn("rule_off", on["explore"])

    def test_tau_n_changes_the_stencil(self):
        counts = []
        for tau in ("0.1", "1.5"):
            status, meta = self.server.json("api/stage/stencil.L0.json?" + FRAME + "&tau_n=" + tau)
            self.assertEqual(status, 200, meta)
            counts.append(meta["ones"])
            status, report = self.server.json("api/frame?" + FRAME + "&tau_n=" + tau)
            self.assertEqual(report["levels"][0]["shaded_pixels"], meta["ones"])
        self.assertNotEqual(counts[0], counts[1])

    def test_pan_is_the_motion_knob(self):
        """`pan` (SPEC §13, --pan): motion without a file; the page's knob sends it. 0 is no term."""
        status, still = self.server.json("api/frame?" + FRAME + "&pan=0")
        self.assertEqual(status, 200, still)
        self.assertNotIn("foveation", still)
        self.assertNotIn("motion", still["explore"]["layers"])
        status, moved = self.server.json("api/frame?" + FRAME + "&pan=0.3")
        self.assertEqual(status, 200, moved)
        self.assertAlmostEqual(moved["foveation"]["pan"], 0.3, places=6)
        self.assertTrue(moved["foveation"]["motion"])
        self.assertIn("motion", moved["explore"]["layers"])
        self.assertIn("levellimit", moved["explore"]["layers"])
        # what moves takes coarser levels: fewer level-0 pixels shaded than the still frame
        self.assertLess(moved["levels"][0]["shaded_pixels"], still["levels"][0]["shaded_pixels"])
        by_limit = moved["foveation"]["pixels_by_level_limit"]
        self.assertEqual(sum(by_limit), 320 * 180)
        self.assertGreater(sum(by_limit[1:]), 1000)  # moved past level 1's 4 px threshold
        status, meta = self.server.json("api/stage/motion.json?" + FRAME + "&pan=0.3")
        self.assertEqual(status, 200, meta)
        status, bad = self.server.json("api/frame?" + FRAME + "&pan=2e6")
        self.assertEqual(status, 400, bad)
        self.assertEqual(bad["parameter"], "pan")
        status, _, page = self.server.get("")
        self.assertIn(b'data-param="pan"', page)

    def test_every_layer_is_a_png_with_a_legend(self):
        status, report = self.server.json("api/frame?" + FRAME)
        for layer in report["explore"]["layers"]:
            status, ctype, body = self.server.get("api/stage/%s.png?%s" % (layer, FRAME))
            self.assertEqual(status, 200, layer)
            self.assertEqual(ctype, "image/png", layer)
            self.assertEqual(body[:8], b"\x89PNG\r\n\x1a\n", layer)
            status, meta = self.server.json("api/stage/%s.json?%s" % (layer, FRAME))
            self.assertEqual(status, 200, layer)
            self.assertIn(meta["kind"], ("binary", "effect", "scalar", "colour", "levels", "flip", "reason"))
            self.assertLessEqual(meta["lo"], meta["hi"], layer)

    def test_flip_layer_against_full(self):
        # The LDR-FLIP map of the method's final against full, with its magma legend and
        # mean; the report's figure is the same number, and full against itself is 0 everywhere.
        status, report = self.server.json("api/frame?" + FRAME)
        self.assertEqual(status, 200, report)
        self.assertEqual(report["explore"]["layers"][-2:], ["difference", "flip"])
        status, meta = self.server.json("api/stage/flip.json?" + FRAME)
        self.assertEqual(status, 200, meta)
        self.assertEqual((meta["kind"], meta["lo"], meta["hi"], meta["channels"]), ("flip", 0.0, 1.0, ["flip"]))
        self.assertTrue(meta["ramp"].startswith("linear-gradient(to right,rgb(0,0,4)"), meta["ramp"])
        self.assertGreater(meta["mean"], 0.0)
        self.assertAlmostEqual(meta["mean"], report["error_vs_full"]["flip"]["mean"], places=6)
        self.assertIn("LDR-FLIP", meta["caption"])
        status, ctype, body = self.server.get("api/stage/flip.png?" + FRAME)
        self.assertEqual((status, ctype, body[:4]), (200, "image/png", b"\x89PNG"))
        status, v = self.server.json("api/value?layer=flip&x=160&y=90&" + FRAME)
        self.assertEqual(status, 200, v)
        self.assertTrue(0.0 <= v["values"]["flip"] <= 1.0, v)
        status, meta = self.server.json("api/stage/flip.json?method=full&" + FRAME)
        self.assertEqual(status, 200, meta)
        self.assertEqual(meta["mean"], 0.0)
        self.assertIn("flip", {step["part"] for step in self.info["teach"]})

    def test_every_effect_and_method_has_its_layers(self):
        for effect, method, samples in [("ssm", "mrr", 16), ("ssgi", "mrr", 8), ("ssao", "tiles", 8),
                                        ("ssao", "uniform-2", 8), ("ssao", "full", 8)]:
            q = f"effect={effect}&method={method}&samples={samples}&size=160x90&never_slower=off"
            status, report = self.server.json("api/frame?" + q)
            self.assertEqual(status, 200, (q, report))
            layers = report["explore"]["layers"]
            if effect == "ssm":
                self.assertTrue({"shadowmap", "shadowtest", "edges.shadow"} <= set(layers), layers)
            if method == "tiles":
                self.assertIn("tilerates", layers)
            for layer in layers:
                status, ctype, body = self.server.get("api/stage/%s.png?%s" % (layer, q))
                self.assertEqual((status, ctype), (200, "image/png"), (q, layer, body[:200]))
            status, probe = self.server.json("api/probe?x=80&y=45&path=cpu&" + q)
            self.assertEqual(status, 200, (q, probe))
            if self.port:  # the port's frame of every mode, its difference and the probe of both
                for layer in ("final", layers[len(layers) // 2]):
                    status, ctype, body = self.server.get("api/stage/%s.png?path=both&%s" % (layer, q))
                    self.assertEqual((status, ctype), (200, "image/png"), (q, layer, body[:200]))
                status, both = self.server.json("api/probe?x=80&y=45&path=both&" + q)
                self.assertEqual(status, 200, (q, both))

    def test_mrr_effect_layers_and_the_why(self):
        # SPEC 12.3: mrr-effect's arms as layers, and the why layer's code is the probe's reason
        reasons = ["none", "geometry", "effect", "marks", "closure", "coarsest", "fallback", "limit", "trim"]
        # the arms without SPEC 12.5's trim (which the trim's own check below covers)
        q = "effect=ssao&method=mrr-effect&samples=8&size=160x90&never_slower=off&effect_posterior=0.05&effect_trim=off"
        status, report = self.server.json("api/frame?" + q)
        self.assertEqual(status, 200, report)
        layers = report["explore"]["layers"]
        for layer in ("mask.L1.geometry", "mask.L1.footprint", "mask.L1.marks", "mask.L1.why", "mask.L3.why"):
            self.assertIn(layer, layers)
            status, ctype, body = self.server.get("api/stage/%s.png?%s" % (layer, q))
            self.assertEqual((status, ctype), (200, "image/png"), (layer, body[:200]))
        self.assertNotIn("mask.L3.geometry", layers)  # the coarsest level is not widened
        seen = set()
        for x, y in [(80, 45), (10, 80), (150, 10), (40, 60)]:
            status, probe = self.server.json("api/probe?x=%d&y=%d&path=cpu&%s" % (x, y, q))
            self.assertEqual(status, 200, probe)
            for level in range(4):
                why = probe["levels"][level]["why"]
                status, v = self.server.json("api/value?layer=mask.L%d.why&x=%d&y=%d&%s" % (level, x, y, q))
                self.assertEqual(status, 200, v)
                self.assertEqual(reasons[int(v["values"]["why"])], why["reason"], (x, y, level))
                self.assertEqual(why["reason"] not in ("none", "limit"), probe["levels"][level]["S"] == 1)
                seen.add(why["reason"])
        self.assertEqual(probe["levels"][3]["why"]["reason"], "coarsest")
        status, meta = self.server.json("api/stage/mask.L1.why.json?" + q)
        self.assertEqual((meta["kind"], meta["names"][:3]), ("reason", ["none", "geometry", "effect"]))
        self.assertEqual(len(meta["swatches"]), len(reasons))
        self.assertTrue({"geometry", "coarsest"} <= seen, seen)
        # SPEC 12.5, the trim (on by default): a level pixel it cut says so, and is not shaded
        qt = q.replace("&effect_trim=off", "")
        trimmed = 0
        for x, y in [(80, 45), (10, 80), (150, 10), (40, 60), (120, 70)]:
            status, probe = self.server.json("api/probe?x=%d&y=%d&path=cpu&%s" % (x, y, qt))
            self.assertEqual(status, 200, probe)
            for level in range(1, 4):
                why = probe["levels"][level]["why"]
                status, v = self.server.json("api/value?layer=mask.L%d.why&x=%d&y=%d&%s" % (level, x, y, qt))
                self.assertEqual(reasons[int(v["values"]["why"])], why["reason"], (x, y, level))
                self.assertEqual(why["reason"] not in ("none", "limit", "trim"), probe["levels"][level]["S"] == 1)
                trimmed += why["reason"] == "trim"
        self.assertGreater(trimmed, 0, "no probed level pixel was trimmed: the check is vacuous")
        # each knob of mrr-effect is a different frame, not the cached one
        # (a priori: at 160x90 the budget finds no time left, so it would shade what the a priori masks do)
        base = "effect=ssao&method=mrr-effect&samples=8&size=160x90&never_slower=off&effect_budget=0"
        shaded = set()
        for knob in ("", "&effect_only=1", "&effect_cap=2", "&effect_scale=0.5", "&effect_first_level=2",
                     "&effect_posterior=0.05"):
            status, frame = self.server.json("api/frame?" + base + knob)
            self.assertEqual(status, 200, frame)
            shaded.add((knob, frame["shaded_pixels_total"]))
        self.assertEqual(len({n for _, n in shaded}), len(shaded), shaded)
        status, mrr = self.server.json("api/frame?effect=ssao&method=mrr&samples=8&size=160x90&never_slower=off")
        self.assertIn("mask.L1.why", mrr["explore"]["layers"])
        self.assertNotIn("mask.L1.footprint", mrr["explore"]["layers"])

    def test_value_under_a_pixel(self):
        status, v = self.server.json("api/value?layer=alpha.L1&x=101&y=51&" + FRAME)
        self.assertEqual(status, 200, v)
        self.assertEqual(v["grid_pixel"], [50, 25])
        self.assertIn("a", v["values"])

    def test_probe_oracle(self):
        status, probe = self.server.json("api/probe?x=160&y=90&path=cpu&" + FRAME)
        self.assertEqual(status, 200, probe)
        self.assertEqual(probe["pixel"], [160, 90])
        self.assertEqual(len(probe["levels"]), 4)
        self.assertIn("final", probe)

    def test_probe_both_and_the_port(self):
        self.need_port()
        status, both = self.server.json("api/probe?x=160&y=90&path=both&" + FRAME)
        self.assertEqual(status, 200, both)
        self.assertIn("first_difference", both)
        self.assertEqual(both["oracle"]["pixel"], both["port"]["pixel"])
        self.assertTrue(all({"key", "oracle", "port", "differs"} <= set(r) for r in both["rows"]))
        status, ctype, body = self.server.get("api/stage/final.png?path=gpu&" + FRAME)
        self.assertEqual((status, ctype), (200, "image/png"))
        status, meta = self.server.json("api/stage/stencil.L0.json?path=both&" + FRAME)
        self.assertEqual(status, 200, meta)
        self.assertEqual(meta["kind"], "difference")
        status, report = self.server.json("api/frame?path=gpu&" + FRAME)
        self.assertEqual(report["path"], "gpu")
        self.assertIn("renderer", report)

    # -- a probed pixel's stochastic stages against the oracle's seeds ---------------
    def test_noise_probe_mean_interval_and_where_the_value_falls(self):
        frame = "effect=ssao&samples=12&size=320x180"  # a frame no other test renders: its seeds are not cached
        seen, done = set(), threading.Event()

        def watch():  # the seeds show in the progress while they render
            while not done.is_set():
                _, p = self.server.json("api/progress")
                if "noise-aware seed" in (p.get("job") or ""):
                    seen.add(p["job"])
                time.sleep(0.03)

        watcher = threading.Thread(target=watch)
        watcher.start()
        try:
            status, j = self.server.json("api/noise?x=160&y=90&path=cpu&" + frame)
        finally:
            done.set()
            watcher.join()
        self.assertEqual(status, 200, j)
        self.assertTrue(any(s.startswith("oracle: noise-aware seed ") and s.endswith("/16") for s in seen), seen)
        self.assertEqual((j["pixel"], j["seeds"], j["samples"], j["path"]), ([160, 90], 16, 12, "cpu"))
        self.assertFalse(j["reference_cached"])
        self.assertIn("--seed 0", j["subject"])
        stages = {s["stage"]: s for s in j["stages"]}
        self.assertTrue({"raw.L0", "sub.L0", "raw.L3", "final", "shaded"} <= set(stages), sorted(stages))
        self.assertEqual(stages["raw.L0"]["shader"], "ssao.frag")
        shaded = [s for s in j["stages"] if s["shaded"]]
        self.assertIn("final", [s["stage"] for s in shaded])
        for s in shaded:
            self.assertGreater(s["stage_pixels"], 0, s)
            self.assertAlmostEqual(s["sidak_level"], 1 - 0.99 ** (1 / (s["stage_pixels"] * len(s["channels"]))), delta=1e-9)
            for c in s["channels"]:
                lo, hi = c["accepted"]
                self.assertLessEqual(lo, c["mean"], s["stage"])
                self.assertLessEqual(c["mean"], hi, s["stage"])
                self.assertLessEqual(c["mean_interval_95"][0], c["mean"])
                self.assertEqual(c["inside"], lo <= c["value"] <= hi, (s["stage"], c))
        # The oracle's own frame at seed 0 is another draw of the estimator: inside here.
        self.assertTrue(j["inside"], j)
        # The value is the probe's: the same frame.
        _, probe = self.server.json("api/probe?x=160&y=90&path=cpu&" + frame)
        self.assertAlmostEqual(stages["final"]["channels"][0]["value"], probe["final"], places=6)
        # Another pixel of the same frame reads the cached seeds, at once.
        start = time.monotonic()
        status, k = self.server.json("api/noise?x=40&y=30&path=cpu&" + frame)
        self.assertEqual(status, 200, k)
        self.assertTrue(k["reference_cached"])
        self.assertLess(time.monotonic() - start, 5.0)
        # No stochastic stage, or more seeds than the budget allows: 400 naming the parameter.
        status, e = self.server.json("api/noise?x=1&y=1&effect=ssm&samples=9&size=320x180")
        self.assertEqual((status, e["parameter"]), (400, "effect"), e)
        self.assertIn("no stochastic stage", e["error"])
        status, e = self.server.json("api/noise?x=1&y=1&effect=ssao&samples=64&size=1280x720")
        self.assertEqual((status, e["parameter"]), (400, "size"), e)
        self.assertIn("noise-aware: the oracle's 16 seeds of this frame are an estimated", e["error"])
        status, e = self.server.json("api/noise?x=400&y=1&" + frame)
        self.assertEqual((status, e["parameter"]), (400, "x"), e)

    def test_noise_probe_of_the_port(self):
        self.need_port()
        status, j = self.server.json("api/noise?x=160&y=90&path=both&" + FRAME)
        self.assertEqual(status, 200, j)
        self.assertEqual(j["path"], "gpu")
        self.assertIn("the port (", j["subject"])
        _, both = self.server.json("api/probe?x=160&y=90&path=both&" + FRAME)
        final = [s for s in j["stages"] if s["stage"] == "final"][0]["channels"][0]
        self.assertAlmostEqual(final["value"], both["port"]["final"], places=6)
        self.assertTrue(j["inside"], j)  # the port draws mrr's own samples: the seed-0 frame, inside

    # -- bad input ------------------------------------------------------------------------
    def test_bad_parameters_are_400_naming_the_parameter(self):
        cases = [
            ("api/frame?tau_n=abc", "tau_n"), ("api/frame?tau_n=5", "tau_n"), ("api/frame?tau_z=-1", "tau_z"),
            ("api/frame?samples=0", "samples"), ("api/frame?samples=x", "samples"), ("api/frame?size=12", "size"),
            ("api/frame?size=100000x100000", "size"), ("api/frame?size=16384x16384", "size"), ("api/frame?effect=nope", "effect"),
            ("api/frame?method=nope", "method"), ("api/frame?disable_level=7", "disable_level"),
            ("api/frame?sigma2=1,2", "sigma2"), ("api/frame?weights=1,1,1,-1", "weights"),
            ("api/frame?eye=1,2", "eye"), ("api/frame?bogus=1", "bogus"), ("api/frame?path=cuda", "path"),
            ("api/frame?scene=/etc/passwd", "scene"), ("api/frame?scene=../../../etc/passwd", "scene"),
            ("api/frame?scene=builtin:nope", "scene"), ("api/frame?cost_model=/etc/passwd", "cost_model"),
            ("api/frame?threads=64", "threads"), ("api/frame?flip_up=maybe", "flip_up"),
            ("api/probe?x=320&y=0", "x"), ("api/probe?x=0", "y"), ("api/probe?x=-1&y=0", "x"),
            ("api/probe?x=1&y=1&path=all", "path"), ("api/value?x=1&y=1", "layer"),
            ("api/stage/final.png?gain=0", "gain"), ("api/stage/final.png?path=nope", "path"),
        ]
        for path, parameter in cases:
            status, ctype, body = self.server.get(path)
            self.assertEqual(status, 400, (path, body))
            self.assertTrue(ctype.startswith("application/json"), path)
            error = json.loads(body)
            self.assertEqual(error["parameter"], parameter, (path, error))
            self.assertTrue(error["error"], path)

    def test_unknown_layers_and_paths_are_404(self):
        for path in ["api/stage/nope.png", "api/stage/stencil.L9.png", "api/stage/gbuffer.L0.nope.json",
                     "api/nope", "nope.html", "api/value?layer=nope&x=1&y=1"]:
            status, ctype, body = self.server.get(path)
            self.assertEqual(status, 404, (path, body))
            self.assertIn("error", json.loads(body), path)

    def test_path_traversal_is_refused(self):
        for path in ["/api/stage/..%2f..%2fetc%2fpasswd.png", "/api/stage/../../../etc/passwd.png",
                     "/../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/explore.js/../../etc/passwd",
                     "/api/stage/%2e%2e%2fREADME.md.png", "/api/frame?scene=" + urllib.parse.quote("../README.md")]:
            status, ctype, body = self.raw_status(path)
            self.assertGreaterEqual(status, 400, path)
            self.assertLess(status, 500, path)
            self.assertNotIn(b"root:", body, path)

    def test_other_methods_do_not_crash(self):
        host, port = self.server.url[len("http://"):-1].split(":")
        for method in ("POST", "PUT", "DELETE"):
            conn = http.client.HTTPConnection(host, int(port), timeout=30)
            conn.request(method, "/api/frame", body=b"x")
            self.assertGreaterEqual(conn.getresponse().status, 400)
            conn.close()
        self.assertTrue(self.server.alive())

    def test_odd_frames_never_crash_the_server(self):
        """Seeded combinations of odd but legal (and some illegal) values at tiny sizes: every
        answer is JSON or a PNG, 2xx or 4xx (503 without the port), and the server lives on."""
        import random
        rng = random.Random(20)
        choices = {
            "size": ["1x1", "7x3", "33x17", "64x36", "2x200"],
            "effect": ["ssao", "ssm", "ssgi"],
            "method": ["mrr", "full", "uniform-1", "uniform-2", "tiles", "multires"],
            "samples": ["1", "4", "9", "3"],
            "tau_n": ["0", "2", "0.0001", "nan", "1e9"],
            "tau_z": ["0", "1e-9", "100", "inf"],
            "sigma2": ["0,0,0,0", "64,64,64,64", "0.5,1,2,4", "1,1,1,65"],
            "weights": ["0,0,0,0", "1e6,1e6,1e6,1e6", "1,1,1,1"],
            "disable_level": [["1"], ["1", "2", "3"], ["3"], ["2", "3"]],
            "never_slower": ["on", "off"],
            "fov": ["0.5", "170", "179", "0"],
            "eye": ["0,0,100", "1e30,0,0", "0,1,0"],
            "shadow_map_size": ["16", "64", "15"],
            "light_angle": ["0.001", "0.5", "0"],
        }
        for i in range(40):
            params = [("path", rng.choice(["cpu", "gpu"] if self.port else ["cpu"]))]
            for key in rng.sample(sorted(choices), rng.randint(2, 6)):
                value = rng.choice(choices[key])
                params += [(key, v) for v in value] if isinstance(value, list) else [(key, value)]
                if key == "eye":
                    params.append(("target", "0,0,0"))
            q = urllib.parse.urlencode(params)
            for endpoint in ("api/frame?", "api/probe?x=0&y=0&", "api/stage/final.png?"):
                status, ctype, body = self.server.get(endpoint + q)
                self.assertTrue(200 <= status < 300 or 400 <= status < 500 or status == 503, (status, q, body[:300]))
                self.assertTrue(ctype.startswith("application/json") or ctype == "image/png", (q, ctype))
                if status >= 400:
                    self.assertIn("error", json.loads(body))
            self.assertTrue(self.server.alive(), "the server died on " + q)

    # -- concurrency ----------------------------------------------------------------------
    def test_concurrent_requests_queue_and_agree(self):
        frames = ["api/frame?%s&tau_z=%s" % (FRAME, tau) for tau in ("0.03", "0.05")]
        requests = [frames[i % 2] for i in range(8)]
        requests += ["api/stage/stencil.L1.png?%s&tau_z=0.03" % FRAME, "api/probe?x=5&y=5&%s&tau_z=0.05" % FRAME]
        requests += ["api/frame?tau_n=9", "api/progress"]
        with ThreadPoolExecutor(max_workers=len(requests)) as pool:
            results = list(pool.map(lambda p: (p, self.server.get(p)), requests))
        bodies = {}
        for path, (status, ctype, body) in results:
            if "tau_n=9" in path:
                self.assertEqual(status, 400)
                continue
            self.assertEqual(status, 200, (path, body[:200]))
            if ctype.startswith("application/json"):
                json.loads(body)
            if path in frames:
                bodies.setdefault(path, set()).add(body)
        for path, seen in bodies.items():
            self.assertEqual(len(seen), 1, "identical requests gave different answers: " + path)
        self.assertNotEqual(bodies[frames[0]], bodies[frames[1]])

    # -- the budget and the host ----------------------------------------------------
    def test_over_budget_is_a_400_naming_the_budget(self):
        budget = self.info["budget"]["budget_m"]
        self.assertEqual(budget, 500)
        for q, parameter in (("effect=ssgi&samples=8192&size=1920x1080", "size"),
                             ("effect=ssgi&samples=8192&size=320x180", "samples"),
                             ("effect=ssao&samples=1024&size=1280x720&method=full", "samples"),
                             ("effect=ssm&samples=1&size=160x90&shadow_map_size=8192", "shadow_map_size")):
            for endpoint in ("api/frame?", "api/stage/final.png?", "api/probe?x=1&y=1&", "api/value?layer=final&x=1&y=1&"):
                status, error = self.server.json(endpoint + q)
                self.assertEqual(status, 400, (endpoint, q, error))
                self.assertEqual(error["parameter"], parameter, (q, error))
                self.assertIn("budget of %g M" % budget, error["error"])
                self.assertIn("--budget", error["error"])
                self.assertEqual(error["budget_m"], budget)
                self.assertGreater(error["work_m"], budget)
            if parameter == "samples":
                self.assertGreater(error["max_samples"], 0)
                # the most that fit pass the budget (x out of range: refused after it, before a render)
                most = q.replace("samples=8192", "samples=%d" % error["max_samples"]).replace(
                    "samples=1024", "samples=%d" % error["max_samples"])
                status, error = self.server.json("api/value?layer=final&x=99999&y=0&" + most)
                self.assertEqual((status, error["parameter"]), (400, "x"), error)
            else:
                self.assertEqual(error["max_samples"], 0)
        status, report = self.server.json("api/frame?" + FRAME)
        self.assertEqual(status, 200)
        self.assertEqual(report["explore"]["budget_m"], budget)
        self.assertLess(report["explore"]["work_m"], budget)
        self.assertEqual(report["explore"]["max_samples"], 1024)  # SSAO's own limit at 320x180

    def raw_request(self, path, headers, method="GET"):
        """(status, headers, body) of a request with exactly these headers (no Host unless given)."""
        host, port = self.server.url[len("http://"):-1].split(":")
        conn = http.client.HTTPConnection(host, int(port), timeout=60)
        conn.putrequest(method, path, skip_host=True, skip_accept_encoding=True)
        for k, v in headers.items():
            conn.putheader(k, v)
        conn.endheaders()
        r = conn.getresponse()
        body = r.read()
        conn.close()
        return r.status, dict((k.lower(), v) for k, v in r.getheaders()), body

    def test_only_the_servers_own_host(self):
        port = self.server.url.rstrip("/").rsplit(":", 1)[1]
        own = "127.0.0.1:" + port
        for host in ("127.0.0.1:" + port, "localhost:" + port, "LOCALHOST:" + port, "[::1]:" + port):
            for path in ("/", "/api/info", "/api/frame?" + FRAME):
                status, headers, body = self.raw_request(path, {"Host": host})
                self.assertEqual(status, 200, (host, path, body[:200]))
        refused = [({"Host": "evil.example.com"}, 421), ({"Host": "evil.example.com:" + port}, 421),
                   ({"Host": "127.0.0.1"}, 421), ({"Host": "127.0.0.1:1"}, 421), ({"Host": "127.0.0.2:" + port}, 421),
                   ({"Host": "localhost.evil.example.com:" + port}, 421), ({}, 421),
                   ({"Host": own, "Sec-Fetch-Site": "cross-site"}, 403),
                   ({"Host": own, "Sec-Fetch-Site": "same-site"}, 403),
                   ({"Host": own, "Origin": "http://evil.example.com"}, 403),
                   ({"Host": own, "Origin": "http://localhost:" + port}, 403)]
        for headers, expected in refused:
            for path in ("/", "/api/info", "/api/frame?" + FRAME, "/api/stage/final.png?" + FRAME, "/nope"):
                status, got, body = self.raw_request(path, headers)
                self.assertEqual(status, expected, (headers, path, body[:200]))
                self.assertIn("error", json.loads(body))
        # the page's own requests: same-origin fetches, a typed URL
        for headers in ({"Host": own, "Sec-Fetch-Site": "same-origin", "Origin": "http://" + own},
                        {"Host": own, "Sec-Fetch-Site": "none"}):
            self.assertEqual(self.raw_request("/api/info", headers)[0], 200, headers)

    def test_no_cors_headers(self):
        own = self.server.url[len("http://"):-1]
        for method, path in (("GET", "/"), ("GET", "/api/info"), ("GET", "/api/frame?" + FRAME),
                             ("GET", "/api/frame?tau_n=9"), ("GET", "/nope"), ("OPTIONS", "/api/info"),
                             ("GET", "/api/info"), ("OPTIONS", "/api/frame")):
            status, headers, _ = self.raw_request(path, {"Host": own, "Origin": "http://" + own,
                                                         "Access-Control-Request-Method": "GET"}, method)
            self.assertFalse([h for h in headers if h.startswith("access-control-")], (method, path, headers))
        status, headers, _ = self.raw_request("/api/info", {"Host": "evil.example.com", "Origin": "http://evil.example.com"})
        self.assertFalse([h for h in headers if h.startswith("access-control-")], headers)

    # -- the command line ---------------------------------------------------------------------
    def test_a_port_in_use_is_one_line_and_exit_2(self):
        port = self.server.url.rstrip("/").rsplit(":", 1)[1]
        r = subprocess.run([MRR, "explore", "--port", port], capture_output=True, text=True, timeout=60)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertTrue(r.stderr.startswith("mrr: error: --port " + port), r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)

    def test_bad_command_line_options_exit_2(self):
        for args in (["--port", "70000"], ["--budget", "0"], ["--budget", "-5"], ["--budget", "nan"],
                     ["--budget", "1", "--size", "320x180"], ["--tau-n", "7"], ["--scene", "builtin:nope"], ["--size", "0x0"],
                     ["--scene", "/nonexistent/scene.gltf"], ["--cost-model", "/nonexistent.json"]):
            r = subprocess.run([MRR, "explore", *args], capture_output=True, text=True, timeout=60)
            self.assertEqual(r.returncode, 2, (args, r.stderr))
            self.assertTrue(r.stderr.startswith("mrr: error: "), (args, r.stderr))

    # -- the re-render figure (docs/explore.md) ---------------------------------------------
    def test_rerender_time(self):
        paths = ["cpu"] + (["gpu"] if self.port else [])
        for path in paths:
            self.server.get("api/frame?%s&path=%s" % (FRAME, path))  # scene, BVH, context, reference
            times = []
            for i in range(5):
                start = time.perf_counter()
                status, _, _ = self.server.get("api/frame?%s&path=%s&tau_n=%.3f" % (FRAME, path, 0.2 + 0.01 * i))
                times.append(time.perf_counter() - start)
                self.assertEqual(status, 200)
            median = statistics.median(times)
            print("re-render 320x180 SSAO-16, %s: median %.0f ms of %d (%s)" %
                  (path, 1000 * median, len(times), ", ".join("%.0f" % (1000 * t) for t in times)), file=sys.stderr)
            # the budget is 1 s on 2 cores; 3 s leaves room for a loaded CI machine
            self.assertLess(median, 3.0, path)


def rss_kib(pid):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS")


class ExploreHoldsUp(unittest.TestCase):
    """The work budget on a server of its own, with a smaller budget (--budget 300) so that its heaviest
    request takes a few seconds here: abandoned and superseded renders stop, and a soak of random
    requests with clients dropping mid-way leaves it answering at once, its memory where it was."""

    BUDGET = 300

    @classmethod
    def setUpClass(cls):
        cls.server = ExploreServer(MRR, "--scene", "builtin:demo", "--threads", "2", "--budget", str(cls.BUDGET))
        host, port = cls.server.url[len("http://"):-1].split(":")
        cls.address = (host, int(port))
        status, cls.info = cls.server.json("api/info")
        assert status == 200, cls.info
        cls.port = cls.info["port"]["available"]
        # The heaviest frame within the budget at the soak's largest size: SSGI at full resolution,
        # 320x180, the most samples that fit (its effect stage is the longest there is at this budget).
        status, error = cls.server.json("api/frame?effect=ssgi&method=full&size=320x180&samples=8192")
        assert status == 400 and error["max_samples"] > 0, error
        cls.heavy = "effect=ssgi&method=full&size=320x180&samples=%d" % error["max_samples"]

    @classmethod
    def tearDownClass(cls):
        alive = cls.server.alive()
        cls.server.stop()
        assert alive, "the server died during the tests:\n" + "".join(cls.server.stderr_lines)

    def send_and_leave(self, path, after):
        """Sends GET path on a connection of its own and closes it `after` seconds later, unanswered."""
        conn = socket.create_connection(self.address)
        conn.sendall(("GET /%s HTTP/1.1\r\nHost: %s:%d\r\n\r\n" % (path, *self.address)).encode())
        time.sleep(after)
        conn.close()

    def timed(self, path):
        start = time.perf_counter()
        status, body = self.server.json(path)
        return status, body, time.perf_counter() - start

    def test_an_abandoned_heavy_request_stops(self):
        status, _, cheap_first = self.timed("api/frame?%s&tau_n=0.11" % FRAME)  # warm: scene, BVH, renderer
        self.assertEqual(status, 200)
        status, _, cheap = self.timed("api/frame?%s&tau_n=0.12" % FRAME)
        self.assertEqual(status, 200)
        # the heavy frame once to its end, for its longest stage
        status, report, whole = self.timed("api/frame?%s&gi_radius=0.5" % self.heavy)
        self.assertEqual(status, 200, report)
        self.assertLessEqual(report["explore"]["work_m"], self.BUDGET)
        longest = max(ms for stage, ms in report["timings_ms"].items() if stage != "total") / 1000
        _, before, _ = self.timed("api/progress")
        delays = []
        for i, after in enumerate((0.1 * whole, 0.6 * whole)):  # in the reference's effect; in the frame's
            self.send_and_leave("api/frame?%s&gi_radius=%.2f" % (self.heavy, 0.6 + 0.1 * i), after)
            status, _, delay = self.timed("api/frame?%s&tau_n=%.2f" % (FRAME, 0.13 + 0.01 * i))
            self.assertEqual(status, 200)
            delays.append(delay)
        _, after, _ = self.timed("api/progress")
        print("abandoned heavy request (%s, %.0f M, %.2f s whole, longest stage %.2f s): the next cheap frame "
              "in %s s (%.2f s alone)" % (self.heavy, report["explore"]["work_m"], whole, longest,
                                          ", ".join("%.2f" % d for d in delays), cheap), file=sys.stderr)
        self.assertEqual(after["cancelled"] - before["cancelled"], 2, after)
        for delay in delays:
            self.assertLess(delay, 5.0)  # the bound
            self.assertLess(delay, longest + cheap + 1.5)  # at most a stage of the abandoned render

    def test_a_newer_request_for_the_same_view_supersedes(self):
        self.server.get("api/frame?%s&tau_n=0.21" % FRAME)
        results = {}

        def older():
            results["older"] = self.timed("api/frame?%s&gi_radius=1.5&view=v1" % self.heavy)

        t = threading.Thread(target=older)
        t.start()
        time.sleep(0.5)
        status, report, newer = self.timed("api/frame?%s&tau_n=0.22&view=v1" % FRAME)
        t.join(60)
        self.assertEqual(status, 200, report)
        status, error, _ = results["older"]
        self.assertEqual(status, 409, error)
        self.assertEqual(error["parameter"], "view")
        self.assertIn("superseded", error["error"])
        self.assertLess(newer, 5.0)
        # another view, or the same frame again, does not supersede
        status, _, _ = self.timed("api/frame?%s&tau_n=0.22&view=v2" % FRAME)
        self.assertEqual(status, 200)

    def test_soak(self):
        """Random requests, at most 160 and 45 s, four clients at a time, one in four leaving mid-way."""
        paths = ["cpu"] + (["gpu"] if self.port else [])
        rng = random.Random(39)

        def frame():
            return "effect=%s&method=%s&size=%s&samples=%d&tau_n=%.2f" % (
                rng.choice(["ssao", "ssm", "ssgi"]), rng.choice(["mrr", "full", "uniform-1", "tiles"]),
                rng.choice(["160x90", "320x180"]), rng.choice([1, 4, 9, 16]), rng.choice([0.05, 0.1, 0.2, 0.4]))

        def request():
            q = frame() + "&path=" + rng.choice(paths)
            return rng.choice([
                "api/frame?" + q, "api/frame?" + q + "&view=soak", "api/stage/final.png?" + q,
                "api/stage/stencil.L0.json?" + q, "api/probe?x=3&y=4&" + q, "api/value?layer=final&x=2&y=2&" + q,
                "api/info", "api/progress", "api/frame?" + q + "&tau_n=9", "api/frame?effect=ssgi&samples=8192&size=1280x720",
                "api/stage/nope.png?" + q, "api/frame?" + self.heavy + "&gi_radius=%.2f" % rng.uniform(2, 3)])

        # Fill the cache (12 frames) and the port's pool of textures with frames like the soak's
        # first: the soak's frames then replace frames like them, and what the server holds after
        # it beyond what it held before is a leak.
        for i in range(24):
            self.server.get("api/frame?%s&path=%s" % (frame(), paths[i % len(paths)]))
        start_rss = rss_kib(self.server.proc.pid)
        plan = [(request(), rng.random() < 0.25, rng.uniform(0.05, 1.0)) for _ in range(160)]
        deadline = time.monotonic() + 45
        counts = {"answered": 0, "left": 0, "skipped": 0}
        lock = threading.Lock()

        def run(item):
            path, leave, after = item
            if time.monotonic() > deadline:
                with lock:
                    counts["skipped"] += 1
                return
            if leave:
                self.send_and_leave(path, after)
                with lock:
                    counts["left"] += 1
                return
            status, _, body = self.server.get(path, timeout=60)
            self.assertTrue(200 <= status < 300 or 400 <= status < 500, (path, status, body[:300]))
            with lock:
                counts["answered"] += 1

        t0 = time.monotonic()
        with ThreadPoolExecutor(max_workers=4) as pool:
            list(pool.map(run, plan))
        soak = time.monotonic() - t0
        self.assertTrue(self.server.alive())
        status, _, at_once = self.timed("api/info")
        self.assertEqual(status, 200)
        status, _, cheap = self.timed("api/frame?%s&tau_n=0.77" % FRAME)
        self.assertEqual(status, 200)
        end_rss = rss_kib(self.server.proc.pid)
        print("soak: %d answered, %d left mid-way, %d skipped in %.1f s; then info in %.3f s, a new frame in %.2f s; "
              "RSS %.0f MiB -> %.0f MiB" % (counts["answered"], counts["left"], counts["skipped"], soak, at_once, cheap,
                                           start_rss / 1024, end_rss / 1024), file=sys.stderr)
        self.assertLess(soak, 120)
        self.assertLess(at_once, 1.0)
        self.assertLess(cheap, 5.0)
        # the cache holds 12 frames of the soak's sizes at most, as it did before: what is left is a leak
        self.assertLess(end_rss, 1.5 * start_rss)


class ExploreWithoutThePort(unittest.TestCase):
    """No EGL device (here: one that does not exist): the oracle alone, and the port refused."""

    def test_the_oracle_alone(self):
        server = ExploreServer(MRR, "--gl-device", "99")
        try:
            status, info = server.json("api/info")
            self.assertEqual(status, 200)
            self.assertFalse(info["port"]["available"])
            self.assertTrue(info["port"]["status"])
            status, report = server.json("api/frame?" + FRAME)
            self.assertEqual(status, 200, report)
            status, ctype, body = server.get("api/stage/final.png?" + FRAME)
            self.assertEqual((status, ctype), (200, "image/png"))
            for path in ("api/frame?path=gpu&" + FRAME, "api/probe?x=1&y=1&path=both&" + FRAME,
                         "api/stage/final.png?path=both&" + FRAME):
                status, error = server.json(path)
                self.assertEqual(status, 503, (path, error))
                self.assertEqual(error["parameter"], "path")
                self.assertIn("unavailable", error["error"])
            self.assertTrue(server.alive())
        finally:
            server.stop()


class ExploreSeeded(unittest.TestCase):
    """`mrr explore --seed N` (SPEC 7.1): the reference draws the frame's seed."""

    def test_full_with_a_seed_is_its_own_reference(self):
        # before, the reference kept seed 0, so a seeded frame's error held the two seeds' noise
        server = ExploreServer(MRR, "--seed", "3")
        try:
            status, report = server.json("api/frame?" + FRAME + "&method=full")
            self.assertEqual(status, 200, report)
            self.assertEqual(report["error_vs_full"]["rms"], 0.0)
            self.assertEqual(report["error_vs_full"]["max_abs"], 0.0)
            status, report = server.json("api/frame?" + FRAME)  # the method against it: some error
            self.assertGreater(report["error_vs_full"]["rms"], 0.0)
        finally:
            server.stop()


if __name__ == "__main__":
    unittest.main(verbosity=2)
