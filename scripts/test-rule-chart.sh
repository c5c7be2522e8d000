#!/usr/bin/env bash
# A one-scene rule sweep (`mrr bench --rule-sweep`, builtin:plane, the oracle, one pair a frame)
# drawn by scripts/rule-chart.py, its outputs checked (ctest: rule_sweep_chart).
#   scripts/test-rule-chart.sh [path/to/mrr]
# Checks: the chart script exits 0 and writes both SVG charts and rule-sweep.md; the Markdown's
# summary row matches sweep.json's summary (frames, right, wrong beyond noise), it gives the
# prediction error of full's rest and names the cost model that decided, and it has a row per frame with the pairs' quartiles; the decisions chart's title counts the frames right. Then
# the same sweep, one kept frame's counts made those of a frame edged everywhere, re-decided by
# `mrr bench --rule-replay` and drawn: the replay says so, and that frame's with-rule time, never
# measured, is "—" and counted as unmeasured.
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
e = s["prediction_error"]["full_rest"]
if f"Predicted against measured: full's rest {100 * e['rms']:.1f}% RMS, median {100 * e['median']:+.1f}%" not in md:
    fail("rule-sweep.md does not give how far full's rest was priced from its times")
if f"Decided with: cpu: {sweep['cost_models']['cpu']}." not in md:
    fail("rule-sweep.md does not name the cost model that decided the sweep")
svg = open(f"{work}/rule-decisions.svg").read()
if f"decision right on {s['right']}/{s['frames']} frames" not in svg:
    fail("the decisions chart's title does not count the frames right")
PY
/usr/bin/python3 - "$work" << 'PY' || fail "no frame the sweep kept to plant a change in"
import json, sys
work = sys.argv[1]
sweep = json.load(open(f"{work}/sweep.json"))
f = next(f for f in sweep["frames"] if f["decision"] == "mrr")
w, h = f["width"], f["height"]
c = f["counts"]
for key in ("shaded", "shaded_hit", "shaded_searched", "reach"):
    c[key] = [((w + (1 << l) - 1) >> l) * ((h + (1 << l) - 1) >> l) for l in range(4)]
c["hit"] = c["searched"] = w * h
c["edge_blocks"] = ((w + 7) // 8) * ((h + 7) // 8)
json.dump(sweep, open(f"{work}/planted.json", "w"))
PY
"$mrr" bench --rule-replay "$work/planted.json" --json "$work/replay.json" > "$work/replay.out" 2> "$work/replay.err" ||
  fail "the replay failed: $(tail -n1 "$work/replay.err")"
mkdir -p "$work/replay"
/usr/bin/python3 "$here/scripts/rule-chart.py" "$work/replay.json" "$work/replay" > /dev/null 2> "$work/chart.err" ||
  fail "rule-chart.py failed on a replay: $(tail -n1 "$work/chart.err")"
md="$work/replay/rule-sweep.md"
grep -q 'Re-decided from the recorded counts by `mrr bench --rule-replay`' "$md" || fail "a replay's page does not say it is one"
grep -q '(1 unmeasured) |$' "$md" || fail "a replay's summary does not count the unmeasured with-rule time"
[ "$(grep -c '^| cpu | builtin:plane |.* | — | ' "$md")" = 1 ] || fail "the replay's fallen-back frame does not show its with-rule time as unmeasured"
echo "$tool: ok"
