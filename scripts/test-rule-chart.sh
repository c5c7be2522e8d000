#!/usr/bin/env bash
# A one-scene rule sweep (`mrr bench --rule-sweep`, builtin:plane, the oracle, one pair a frame)
# drawn by scripts/rule-chart.py, its outputs checked (ctest: rule_sweep_chart).
#   scripts/test-rule-chart.sh [path/to/mrr]
# Checks: the chart script exits 0 and writes both SVG charts and rule-sweep.md; the Markdown's
# summary row matches sweep.json's summary (frames, right, wrong beyond noise) and it has a row
# per frame with the pairs' quartiles; the decisions chart's title counts the frames right.
# Exit 77 (ctest: skipped) when python3 has no matplotlib. Any failure: exit 1 with a reason.
tool=test-rule-chart
source "$(dirname "${BASH_SOURCE[0]}")/lib-test.sh"
/usr/bin/python3 -c 'import matplotlib' 2> /dev/null || skip "python3 has no matplotlib"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

"$mrr" bench --rule-sweep "$work/sweep.json" --paths cpu --scenes builtin:plane --repeats 1 > "$work/sweep.out" 2> "$work/sweep.err" ||
  fail "the sweep failed: $(tail -n1 "$work/sweep.err")"
/usr/bin/python3 "$here/scripts/rule-chart.py" "$work/sweep.json" "$work" > "$work/chart.out" 2> "$work/chart.err" ||
  fail "rule-chart.py failed: $(tail -n1 "$work/chart.err")"
for f in rule-decisions.svg rule-predicted.svg rule-sweep.md; do
  [ -s "$work/$f" ] || fail "rule-chart.py wrote no $f"
done
/usr/bin/python3 - "$work" << 'PY' || exit 1
import json, re, sys
work = sys.argv[1]
sweep = json.load(open(f"{work}/sweep.json"))
s = sweep["summary"]
md = open(f"{work}/rule-sweep.md").read()
def fail(why):
    print(f"test-rule-chart: FAIL: {why}", file=sys.stderr)
    sys.exit(1)
row = f"| {s['frames']} | {s['right']} ({100.0 * s['right'] / s['frames']:.1f}%) | {s['wrong_beyond_noise']} | {s['kept_mrr']} |"
if row not in md:
    fail(f"rule-sweep.md has no summary row {row!r}")
frames = [l for l in md.splitlines() if l.startswith("| cpu | builtin:plane |")]
if len(frames) != len(sweep["frames"]):
    fail(f"rule-sweep.md has {len(frames)} frame rows for {len(sweep['frames'])} frames")
if not all(re.search(r"\| \d+\.\d\d–\d+\.\d\d \|", l) for l in frames):
    fail("a frame row has no pair quartiles")
svg = open(f"{work}/rule-decisions.svg").read()
if f"decision right on {s['right']}/{s['frames']} frames" not in svg:
    fail("the decisions chart's title does not count the frames right")
PY
echo "$tool: ok"
