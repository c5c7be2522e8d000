#!/usr/bin/env bash
# `mrr bench --quick --check` on both paths, its figures checked for sanity, and its HTML page
# loaded in headless Chromium (ctest: bench_quick_report_in_chromium).
#   scripts/test-bench-report.sh [path/to/mrr]
# Checks: the bench exits 0 with --check (full's error 0, no method above its ideal speedup,
# finite figures); the JSON has every method on both paths, the stability and stress runs;
# the CSV has a row per run, the stability CSV one per stability run with FLIP beside RMS; SSAO's
# and SSGI's main-sweep runs carry their error against the expectation (--expectation 2), SSM's
# none, and each path's full differs from it (its seeds draw noise); the
# page loads with no console message, every chart and image
# decodes, and it holds one figure per chart written. Then takes a screenshot for
# docs/images/bench-report.png (MRR_BENCH_SCREENSHOT=path to override, "" to skip).
# Exit 77 (ctest: skipped) when Chromium cannot be had, or when no GL context can be made
# and MRR_REQUIRE_GL is not 1. Any failure: exit 1 with a one-line reason.
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mrr="${1:-$here/build/mrr}"
shot="${MRR_BENCH_SCREENSHOT-$here/docs/images/bench-report.png}"
tool=test-bench-report
# shellcheck source=scripts/lib-chromium.sh
. "$here/scripts/lib-chromium.sh"

[ -x "$mrr" ] || fail "no mrr binary at $mrr"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/profile"

paths=(cpu gpu)
if ! "$mrr" render --path gpu --scene builtin:plane --size 8x8 --samples 1 -q --report "$work/gl.json" > /dev/null 2> "$work/gl.err"; then
  [ "${MRR_REQUIRE_GL:-}" = 1 ] && fail "no GL context, and MRR_REQUIRE_GL=1: $(head -n1 "$work/gl.err")"
  skip "no OpenGL 3.3 context for the port here ($(head -n1 "$work/gl.err"))"
fi

# 1. The quick bench on both paths, with its sanity checks.
start=$(date +%s)
"$mrr" bench --quick --check --expectation 2 --paths "${paths[@]}" --report "$work/report" --json "$work/bench.json" \
  --csv "$work/bench.csv" --markdown "$work/bench.md" > "$work/bench.out" 2> "$work/bench.err"
rc=$?
[ "$rc" -eq 0 ] || fail "mrr bench --quick --check exited $rc: $(grep -m1 -E 'sanity check failed|error' "$work/bench.err" || tail -n1 "$work/bench.err")"
grep -q '^\[bench\] 1/' "$work/bench.err" || fail "no progress lines on stderr"
python3 - "$work/bench.json" "$work/bench.csv" <<'PY' || exit 1
import json, sys
j = json.load(open(sys.argv[1]))
def fail(msg):
    print("test-bench-report: FAIL: " + msg, file=sys.stderr); sys.exit(1)
runs = j["runs"]
if j["sanity_failures"]: fail("sanity failures in the JSON: %s" % j["sanity_failures"][0])
for path in ("cpu", "gpu"):
    for method in ("full", "uniform-1", "uniform-2", "tiles", "mrr"):
        got = [r for r in runs if r["path"] == path and r["method"] == method and r["group"] == "main"]
        if not got: fail("no %s run of %s in the main sweep" % (path, method))
    for group in ("samples", "resolution", "stress"):
        if not [r for r in runs if r["path"] == path and r["group"] == group]: fail("no %s %s runs" % (path, group))
    if not [r for r in runs if r["path"] == path and r["method"] == "mrr+norule"]: fail("no mrr+norule stress run")
    if not [s for s in j["stability"] if s["path"] == path]: fail("no %s stability runs" % path)
for r in runs:
    if r["method"] == "full" and (r["rms"] != 0 or r["ideal_speedup"] != 1): fail("full has error or ideal != 1: %s" % r)
    if r["ideal_speedup"] <= 0 or r["measured_speedup"] <= 0: fail("non-positive speedup: %s" % r)
rows = open(sys.argv[2]).read().strip().split("\n")
if len(rows) != len(runs) + 1: fail("CSV has %d rows for %d runs" % (len(rows) - 1, len(runs)))
for s in j["stability"]:  # FLIP beside RMS in the flicker table
    if not (0 <= s["flip_flicker"] <= 1 and 0 <= s["mean_flip"] <= 1): fail("stability FLIP outside [0,1]: %s" % s)
for r in runs:  # --expectation: the main sweep's SSAO and SSGI against full's mean over other seeds, SSM none
    if (r["group"] == "main" and r["effect"] != "ssm") != ("rms_expectation" in r):
        fail("rms_expectation where it should not be, or none: %s" % r)
for path in ("cpu", "gpu"):  # each path draws its own noise anew with the seed
    if not [r for r in runs if r["path"] == path and r["method"] == "full" and r.get("rms_expectation", 0) > 0]:
        fail("%s: full has no noise against the expectation" % path)
stab = open(sys.argv[2][:-len(".csv")] + "-stability.csv").read().strip().split("\n")
if len(stab) != len(j["stability"]) + 1 or ",flip_flicker,mean_flip," not in stab[0]:
    fail("the stability CSV has %d rows for %d stability runs, header %s" % (len(stab) - 1, len(j["stability"]), stab[0]))
PY
seconds=$(( $(date +%s) - start ))

# 2. The page, offline in Chromium.
find_chromium
page="$work/report/index.html"
[ -s "$page" ] || fail "no $page"
charts=$(ls "$work/report/charts/"*.svg 2> /dev/null | wc -l)
pngs=$(ls "$work/report/charts/"*.png 2> /dev/null | wc -l)
[ "$charts" -ge 20 ] && [ "$charts" -eq "$pngs" ] || fail "$charts SVG and $pngs PNG charts written"
if grep -Eqi '(src|href)="(https?:|//|file:)' "$page"; then fail "the page references an external resource"; fi
flags=("${chromium_flags[@]}" --user-data-dir="$work/profile")
timeout 60 "$chromium" "${flags[@]}" --dump-dom "file://$page" > "$work/dom.html" 2> "$work/chromium.err" ||
  fail "chromium --dump-dom failed: $(grep -m1 -E 'ERROR|FATAL' "$work/chromium.err")"
if grep -Eq "$chromium_console" "$work/chromium.err"; then
  fail "console message in chromium: $(grep -Em1 "$chromium_console" "$work/chromium.err" | cut -c1-200)"
fi
figures=$(grep -o '<figure id=' "$work/dom.html" | wc -l)
[ "$figures" -eq "$charts" ] || fail "the page shows $figures charts of $charts written"
images=$(grep -Eo 'data-images="[0-9]+"' "$work/dom.html" | grep -Eo '[0-9]+')
loaded=$(grep -Eo 'data-loaded="[0-9]+"' "$work/dom.html" | grep -Eo '[0-9]+')
[ -n "$images" ] && [ -n "$loaded" ] || fail "the page's load script did not run"
[ "$loaded" -eq "$images" ] || fail "$loaded of $images images decoded in chromium"
grep -q 'id="sanity"' "$work/dom.html" || fail "no sanity section"

# 3. The screenshot for the docs.
if [ -n "$shot" ] && [ -w "$(dirname "$shot")" ]; then
  timeout 60 "$chromium" "${flags[@]}" --window-size=1300,1600 --screenshot="$work/shot.png" "file://$page" \
    > /dev/null 2>&1 && [ -s "$work/shot.png" ] && cp "$work/shot.png" "$shot.tmp.$$" && mv "$shot.tmp.$$" "$shot"
fi
echo "$tool: OK: bench --quick on ${paths[*]} in ${seconds}s, sanity passed, $charts charts and $images images decoded"
