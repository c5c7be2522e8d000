#!/usr/bin/env bash
# scripts/gpu-figures.sh --small on the GL port at hand (llvmpipe in CI), its outputs checked
# (ctest: gpu_figures_small).
#   scripts/test-gpu-figures.sh [path/to/mrr]
# Checks: bad usage and a missing GL context each stop it with exit 2 and one
# "gpu-figures: error:" line; the small run exits 0 with "[gpu-figures] step k/n" progress on
# stderr; every compare passed (compare.json); each bench JSON has a main-sweep record of every
# method on the gpu path, the sweeps JSON its samples and resolution sweeps, the passes JSON
# mrr's draws per stage (--gpu-timing passes); Figs. 6, 7 and 9
# were drawn (when python3 has jinja2 and matplotlib); README.md names the GL renderer, lists
# every step with its wall time and the commands run.
# Exit 77 (ctest: skipped) when no GL context can be made and MRR_REQUIRE_GL is not 1.
# Any failure: exit 1 with a one-line reason.
tool=test-gpu-figures
source "$(dirname "${BASH_SOURCE[0]}")/lib-test.sh"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
script="$here/scripts/gpu-figures.sh"
# $OUT means the device machine's result folder to gpu-figures.sh: not here.
run() { env -u OUT bash "$script" "$@"; }

if ! "$mrr" render --path gpu --scene builtin:plane --size 8x8 --samples 1 -q --report "$work/gl.json" > /dev/null 2> "$work/gl.err"; then
  [ "${MRR_REQUIRE_GL:-}" = 1 ] && fail "no GL context, and MRR_REQUIRE_GL=1: $(head -n1 "$work/gl.err")"
  skip "no OpenGL 3.3 context for the port here ($(head -n1 "$work/gl.err"))"
fi
renderer="$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["renderer"])' "$work/gl.json")" ||
  fail "the render report has no renderer"

# 1. Bad usage, and no GL context: exit 2, one line.
expect2() {  # expect2 WHAT PATTERN ARGS...
  local what="$1" pattern="$2" rc
  shift 2
  "$@" > "$work/e.out" 2> "$work/e.err"
  rc=$?
  [ "$rc" -eq 2 ] || fail "$what: exit $rc, expected 2 ($(tail -n1 "$work/e.err"))"
  if [ "$(wc -l < "$work/e.err")" -ne 1 ] || ! grep -Eq "^gpu-figures: error: $pattern" "$work/e.err"; then
    fail "$what: expected one line 'gpu-figures: error: $pattern...', got: $(head -c 300 "$work/e.err")"
  fi
}
expect2 "an unknown option" "unknown option --bogus" run --bogus
expect2 "a bad --cameras" "--cameras x: expected a whole number" run --small --cameras x
expect2 "an unknown step" "--steps: unknown step 'nope'" run --small --steps nope --mrr "$mrr"
expect2 "a missing binary" "no mrr binary at $work/none" run --small --mrr "$work/none"
# No EGL vendor library (glvnd reads this list): no context. Where that does not stop GL, unchecked.
noegl=(env -u OUT __EGL_VENDOR_LIBRARY_FILENAMES="$work/none.json")
if ! "${noegl[@]}" "$mrr" render --path gpu --scene builtin:plane --size 8x8 --samples 1 -q --report "$work/gl2.json" > /dev/null 2>&1; then
  expect2 "no GL context" "no OpenGL 3.3 context: " "${noegl[@]}" bash "$script" --small --mrr "$mrr" --out "$work/nogl"
  [ ! -e "$work/nogl/README.md" ] || fail "no GL context, yet a README was written"
fi

# 2. The small run.
out="$work/out"
start=$(date +%s)
run --small --mrr "$mrr" --out "$out" > "$work/run.out" 2> "$work/run.err"
rc=$?
seconds=$(( $(date +%s) - start ))
if [ "$rc" -ne 0 ]; then
  why="$(python3 -c 'import json, sys; print("; ".join("compare %s %s: %s" % (r["scene"], r["effect"], r["verdict"]) for r in json.load(open(sys.argv[1])) if not r["pass"]))' "$out/compare.json" 2> /dev/null)"
  fail "gpu-figures.sh --small exited $rc: ${why:-$(grep -m1 -E 'error|FAIL|failed' "$work/run.err" || tail -n1 "$work/run.err")}"
fi
grep -q '^\[gpu-figures\] step 1/6: ' "$work/run.err" || fail "no '[gpu-figures] step 1/6: ...' progress line on stderr"
grep -q '^\[gpu-figures\] step 6/6: main-640x360: ok in ' "$work/run.err" || fail "no line saying step 6/6 ended ok"
charts=0
if python3 -c 'import jinja2, matplotlib' 2> /dev/null; then charts=1; fi
python3 - "$out" "$renderer" "$charts" <<'PY' || exit 1
import json, os, sys
out, renderer, charts = sys.argv[1], sys.argv[2], sys.argv[3] == "1"
def fail(msg):
    print("test-gpu-figures: FAIL: " + msg, file=sys.stderr)
    sys.exit(1)
methods = ("full", "uniform-1", "uniform-2", "tiles", "mrr")
effects = ("ssao", "ssm", "ssgi")
c = json.load(open(os.path.join(out, "compare.json")))
if len(c) < 3 or {r["effect"] for r in c} != set(effects): fail("compare.json covers %s" % [(r["scene"], r["effect"]) for r in c])
if "builtin:demo" not in {r["scene"] for r in c}: fail("compare.json has no builtin:demo run")
for r in c:
    if not r["pass"] or r["exit"] != 0: fail("compare %s %s: %s" % (r["scene"], r["effect"], r["verdict"]))
    if not os.path.getsize(os.path.join(out, r["text"])): fail("empty %s" % r["text"])
for name in ("sweeps", "main-160x90", "main-320x180", "main-640x360"):
    p = os.path.join(out, "bench-%s.json" % name)
    if not os.path.exists(p): fail("no bench-%s.json" % name)
    for ext in ("csv", "md"):
        if not os.path.getsize(os.path.join(out, "bench-%s.%s" % (name, ext))): fail("empty bench-%s.%s" % (name, ext))
    j = json.load(open(p))
    if "gpu" not in j["devices"] or renderer not in j["devices"]["gpu"]: fail("bench-%s.json: device %s" % (name, j["devices"]))
    runs = j["runs"]
    if {r["path"] for r in runs} != {"gpu"}: fail("bench-%s.json: paths %s" % (name, {r["path"] for r in runs}))
    for e in effects:
        for m in methods:
            if not [r for r in runs if r["group"] == "main" and r["effect"] == e and r["method"] == m]:
                fail("bench-%s.json: no main-sweep record of %s %s on gpu" % (name, m, e))
    for r in runs:
        if r["measured_speedup"] <= 0 or r["ideal_speedup"] <= 0: fail("bench-%s.json: non-positive speedup %s" % (name, r))
        if r["method"] == "full" and r["rms"] != 0: fail("bench-%s.json: full has RMS %s" % (name, r["rms"]))
    if name == "sweeps":
        for g in ("samples", "resolution"):
            if {r["effect"] for r in runs if r["group"] == g} != set(effects): fail("bench-sweeps.json: the %s sweep misses an effect" % g)
    elif {(r["width"], r["height"]) for r in runs} != {tuple(int(x) for x in name[5:].split("x"))}:
        fail("bench-%s.json: sizes %s" % (name, {(r["width"], r["height"]) for r in runs}))
if charts:
    for f in ["fig%d-gpu-%s.png" % (n, e) for n in (6, 7, 9) for e in effects] + \
             ["main-160x90-speed-vs-rms-gpu-%s.png" % e for e in effects]:
        p = os.path.join(out, f)
        if not os.path.exists(p) or open(p, "rb").read(8) != b"\x89PNG\r\n\x1a\n": fail("no chart %s" % f)
# the passes step: mrr's draws timed alone, per stage, on every effect
pj = json.load(open(os.path.join(out, "bench-passes.json")))
for e in effects:
    rs = [r for r in pj["runs"] if r["method"] == "mrr+norule" and r["effect"] == e]
    if not rs or not rs[0].get("pass_ms"): fail("bench-passes.json: no pass_ms for mrr %s" % e)
    stages = {k.split(" ", 1)[0] for k in rs[0]["pass_ms"]}
    if not {"masks", "blend", "edges"} <= stages: fail("bench-passes.json: mrr %s's passes fall in %s" % (e, sorted(stages)))
if "### Passes (--gpu-timing passes)" not in open(os.path.join(out, "bench-passes.md")).read(): fail("bench-passes.md has no passes table")
readme = open(os.path.join(out, "README.md"), encoding="utf-8").read()
if renderer not in readme: fail("README.md does not name the renderer %r" % renderer)
if "## Where mrr's frame goes, pass by pass" not in readme: fail("README.md has no table of mrr's passes")
for s in ("compare", "passes", "sweeps", "main-160x90", "main-320x180", "main-640x360"):
    if not any(line.startswith("| %s | " % s) and " s | ok |" in line for line in readme.splitlines()):
        fail("README.md has no row saying step %s ran ok with its wall time" % s)
for want in ("mrr compare --scene builtin:demo --effect ssgi", "mrr bench --paths gpu", "--sweep-size 320x180", "date (UTC)"):
    if want not in readme: fail("README.md lacks %r" % want)
PY
# 3. --readme-only rewrites the same page.
cp "$out/README.md" "$work/README.before"
run --small --out "$out" --readme-only 2> "$work/readme.err" || fail "--readme-only: $(tail -n1 "$work/readme.err")"
cmp -s "$out/README.md" "$work/README.before" || fail "--readme-only wrote another README"
echo "$tool: OK: gpu-figures.sh --small on $renderer in ${seconds}s; every compare passed, every method benched, README names the renderer"
