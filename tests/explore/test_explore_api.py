#!/usr/bin/env python3
"""`mrr explore`'s JSON API on its own (issue 20): status codes, content types, bad inputs
(400 naming the parameter, 404 for unknown layers and paths, path traversal), concurrent
requests, a port in use, and the re-render time at 320x180 SSAO-16.

    test_explore_api.py path/to/mrr
Without an EGL device the port's checks are skipped unless MRR_REQUIRE_GL=1."""
import http.client
import json
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

    # -- frames, layers, probes -------------------------------------------------------------
    def test_frame_report(self):
        status, ctype, body = self.server.get("api/frame?" + FRAME)
        self.assertEqual(status, 200)
        self.assertTrue(ctype.startswith("application/json"))
        report = json.loads(body)
        self.assertEqual((report["width"], report["height"], report["samples"]), (320, 180, 16))
        self.assertEqual(len(report["levels"]), 4)
        self.assertGreater(report["ideal_speedup"], 1.0)
        self.assertIn("never_slower", report)
        self.assertIn("error_vs_full", report)
        self.assertGreater(report["explore"]["measured_speedup"], 0.0)
        self.assertIn("stencil.L0", report["explore"]["layers"])

    def test_tau_n_changes_the_stencil(self):
        counts = []
        for tau in ("0.1", "1.5"):
            status, meta = self.server.json("api/stage/stencil.L0.json?" + FRAME + "&tau_n=" + tau)
            self.assertEqual(status, 200, meta)
            counts.append(meta["ones"])
            status, report = self.server.json("api/frame?" + FRAME + "&tau_n=" + tau)
            self.assertEqual(report["levels"][0]["shaded_pixels"], meta["ones"])
        self.assertNotEqual(counts[0], counts[1])

    def test_every_layer_is_a_png_with_a_legend(self):
        status, report = self.server.json("api/frame?" + FRAME)
        for layer in report["explore"]["layers"]:
            status, ctype, body = self.server.get("api/stage/%s.png?%s" % (layer, FRAME))
            self.assertEqual(status, 200, layer)
            self.assertEqual(ctype, "image/png", layer)
            self.assertEqual(body[:8], b"\x89PNG\r\n\x1a\n", layer)
            status, meta = self.server.json("api/stage/%s.json?%s" % (layer, FRAME))
            self.assertEqual(status, 200, layer)
            self.assertIn(meta["kind"], ("binary", "effect", "scalar", "colour", "levels"))
            self.assertLessEqual(meta["lo"], meta["hi"], layer)

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

    # -- the command line ---------------------------------------------------------------------
    def test_a_port_in_use_is_one_line_and_exit_2(self):
        port = self.server.url.rstrip("/").rsplit(":", 1)[1]
        r = subprocess.run([MRR, "explore", "--port", port], capture_output=True, text=True, timeout=60)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertTrue(r.stderr.startswith("mrr: error: --port " + port), r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)

    def test_bad_command_line_options_exit_2(self):
        for args in (["--port", "70000"], ["--tau-n", "7"], ["--scene", "builtin:nope"], ["--size", "0x0"],
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


if __name__ == "__main__":
    unittest.main(verbosity=2)
