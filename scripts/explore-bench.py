#!/usr/bin/env python3
"""The re-render figure of docs/explore.md: `mrr explore` at 320x180 SSAO-16, the time from a
changed knob (tau_n) to the new frame's report, per path, as the page sees it (one HTTP request
to /api/frame; the full-resolution reference is cached, the frame is not).

    scripts/explore-bench.py [path/to/mrr] [scene ...]
Prints a Markdown table on stdout."""
import os
import platform
import statistics
import subprocess
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "tests", "explore"))
from explore_server import ExploreServer  # noqa: E402

mrr = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "build", "mrr")
scenes = sys.argv[2:] or ["builtin:demo", "arcade"]
REPEATS = 10
frame = "effect=ssao&samples=16&size=320x180"

cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), platform.processor())
print(f"`mrr explore`, re-render after a changed tau_n, 320x180 SSAO-16, {REPEATS} changes per row; "
      f"{os.cpu_count()} cores ({cpu})\n")
print("| scene | path | median ms | slowest ms | of which the render ms (median) |")
print("|---|---|---:|---:|---:|")
for scene in scenes:
    server = ExploreServer(mrr, "--scene", scene)
    try:
        status, info = server.json("api/info")
        paths = ["cpu"] + (["gpu"] if info["port"]["available"] else [])
        for path in paths:
            # scene, BVH, GL context and the reference, once
            server.get(f"api/frame?{frame}&path={path}&never_slower=off")
            walls, renders = [], []
            for i in range(REPEATS):
                start = time.perf_counter()
                status, report = server.json(f"api/frame?{frame}&path={path}&never_slower=off&tau_n={0.05 + 0.02 * i:.2f}")
                walls.append(1000 * (time.perf_counter() - start))
                assert status == 200, report
                renders.append(report["explore"]["render_wall_ms"])
            name = "oracle (cpu)" if path == "cpu" else f"port ({report.get('renderer', 'gpu').split('(')[0].strip()})"
            print(f"| {scene} | {name} | {statistics.median(walls):.0f} | {max(walls):.0f} | {statistics.median(renders):.0f} |")
        if len(paths) == 2:  # what the page asks after a change: both reports, then one layer of each and their difference
            walls = []
            for i in range(REPEATS):
                q = f"{frame}&never_slower=off&tau_n={0.061 + 0.02 * i:.3f}"
                start = time.perf_counter()
                for path in paths:
                    server.get(f"api/frame?{q}&path={path}")
                for path in ("cpu", "gpu", "both"):
                    server.get(f"api/stage/stencil.L0.json?{q}&path={path}")
                    server.get(f"api/stage/stencil.L0.png?{q}&path={path}")
                walls.append(1000 * (time.perf_counter() - start))
            print(f"| {scene} | the page: both paths and a layer of each, with their difference | "
                  f"{statistics.median(walls):.0f} | {max(walls):.0f} | |")
    finally:
        server.stop()
