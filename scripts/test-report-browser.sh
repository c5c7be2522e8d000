#!/usr/bin/env bash
# Renders the `mrr compare --report` page in headless Chromium (ctest: compare_report_in_chromium).
#   scripts/test-report-browser.sh [path/to/mrr]
# Makes the report of one frame per effect (arcade from ../shared/scenes when present, else
# builtin:demo), loads it offline in Chromium and checks: no console error, no reference to
# anything outside the page, one <section data-stage> per row `mrr compare` printed, and every
# <img> decoded (the page's inline script counts them on load). Then takes a screenshot for
# docs/images/compare-report.png (override with MRR_REPORT_SCREENSHOT=path, "" to skip).
# Installs Chromium with apt when it is missing; exit 77 (ctest: skipped) when it cannot, or
# when no GL context can be made and MRR_REQUIRE_GL is not 1 (as the GL tests skip).
# Any failure: exit 1 with a one-line reason.
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mrr="${1:-$here/build/mrr}"
scenes="${MRR_SCENES_DIR:-$here/../shared/scenes}"
shot="${MRR_REPORT_SCREENSHOT-$here/docs/images/compare-report.png}"

tool=test-report-browser
# shellcheck source=scripts/lib-chromium.sh
. "$here/scripts/lib-chromium.sh"

[ -x "$mrr" ] || fail "no mrr binary at $mrr"
find_chromium

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/report" "$work/profile"

scene=builtin:demo
[ -f "$scenes/sascha-arcade/subpass_scene_opaque.gltf" ] && scene=arcade

# 1. The report. Exit 1 (a stage over tolerance) still writes the page; 2 is an error.
"$mrr" compare --scene "$scene" --effect all --size 320x180 --samples 16 -q --report "$work/report" \
  > "$work/compare.txt" 2> "$work/compare.err"
rc=$?
if [ "$rc" -gt 1 ] && grep -q 'no EGL device' "$work/compare.err" && [ "${MRR_REQUIRE_GL:-}" != 1 ]; then
  skip "no OpenGL 3.3 context for the port here ($(grep -m1 'no EGL device' "$work/compare.err"))"
fi
[ "$rc" -le 1 ] || fail "mrr compare exited $rc: $(grep -m1 'error' "$work/compare.err" || tail -n1 "$work/compare.err")"
page="$work/report/index.html"
[ -s "$page" ] || fail "mrr compare --report wrote no $page"
rows=$(grep -Ec '^[a-z][A-Za-z0-9_.]*[[:space:]]+(PASS|FAIL|UPSTREAM)[[:space:]]' "$work/compare.txt")
[ "$rows" -gt 0 ] || fail "mrr compare printed no stage rows"
bytes=$(stat -c %s "$page")
[ "$bytes" -le $((8 * 1024 * 1024)) ] || fail "the page is $bytes bytes (over 8 MiB) for a 320x180 frame"
# Self-contained: nothing fetched from anywhere (only data: URIs and #anchors).
if grep -Eqi '(src|href)="(https?:|//|file:)|url\((["'"'"']?)(https?:|//)|@import' "$page"; then
  fail "the page references an external resource: $(grep -Eoi -m1 '(src|href)="(https?:|//|file:)[^"]{0,60}' "$page")"
fi

# 2. Load it offline and dump the DOM after the load event.
flags=("${chromium_flags[@]}" --user-data-dir="$work/profile")
timeout 50 "$chromium" "${flags[@]}" --dump-dom "file://$page" > "$work/dom.html" 2> "$work/chromium.err"
rc=$?
[ "$rc" -eq 0 ] || fail "chromium --dump-dom exited $rc: $(grep -m1 -E 'ERROR|FATAL' "$work/chromium.err")"
[ -s "$work/dom.html" ] || fail "chromium dumped an empty DOM"
# The page logs nothing, so any console line (Chromium prints them all as INFO:CONSOLE) fails.
if grep -Eq "$chromium_console" "$work/chromium.err"; then
  fail "console message in chromium: $(grep -Em1 "$chromium_console" "$work/chromium.err" | cut -c1-200)"
fi

sections=$(grep -Eo '<section class="stage[^"]*" id="[^"]+" data-effect="[a-z]+" data-stage="[^"]+"' "$work/dom.html" | wc -l)
[ "$sections" -eq "$rows" ] || fail "the page has $sections stage sections, mrr compare printed $rows rows"
imgs=$(grep -o '<img ' "$work/dom.html" | wc -l)
[ "$imgs" -gt 0 ] || fail "the page has no <img>"
loaded=$(grep -Eo '<body[^>]*data-loaded="[0-9]+"' "$work/dom.html" | grep -Eo '[0-9]+"$' | tr -d '"')
[ -n "$loaded" ] || fail "the page's load script did not run (no data-loaded on <body>)"
[ "$loaded" -eq "$imgs" ] || fail "$loaded of $imgs images decoded in chromium"
grep -q 'Uncaught' "$work/dom.html" && fail "an error message is in the DOM"
for effect in ssao ssm ssgi; do
  grep -q "id=\"$effect-summary\"" "$work/dom.html" || fail "no summary for $effect"
done

# 3. The screenshot for the docs.
if [ -n "$shot" ]; then
  timeout 50 "$chromium" "${flags[@]}" --window-size=1400,1000 --screenshot="$work/shot.png" "file://$page" \
    > /dev/null 2> "$work/shot.err" || fail "chromium --screenshot failed: $(grep -m1 -E 'ERROR|FATAL' "$work/shot.err")"
  [ -s "$work/shot.png" ] || fail "chromium wrote no screenshot"
  shotBytes=$(stat -c %s "$work/shot.png")
  [ "$shotBytes" -le $((500 * 1024)) ] || fail "the screenshot is $shotBytes bytes (over 500 KB)"
  if [ -w "$(dirname "$shot")" ]; then
    cp "$work/shot.png" "$shot.tmp.$$" && mv "$shot.tmp.$$" "$shot" || fail "cannot write $shot"
  fi
fi

echo "test-report-browser: OK: $scene, $rows stage sections, $imgs images decoded, page $bytes bytes"
