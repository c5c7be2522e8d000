#!/usr/bin/env bash
# Checks that `mrr compare --effect all` passes for the paper's mrr and for mrr-effect on every
# built-in and shared scene (docs/figures.md, "mrr-effect and its ablation"): `mrr compare` on each
# scene at 320x180 (each effect at its default samples), for mrr, for mrr-effect as it ships (its
# a-posteriori term spending a budget in predicted time, docs/spec.md §12.4), a priori
# (--effect-budget 0, §12), with the a-posteriori term by τ_v (§12.2, the bench's +b0+c4+p0.15:
# --effect-budget 0 --effect-cap 4 --effect-posterior 0.15), and for the ablation's effect-only arm
# (§12.3).
# Prints a Markdown table (one row per scene, one cell per variant and effect: the verdict, the
# last word of compare's verdict line for that effect) and exits 1 when any run is not PASS. Logs
# under OUT (default a temporary dir).
#   usage: scripts/compare-effect-sweep.sh [OUT]      (MRR=path/to/mrr to choose the binary)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mrr="${MRR:-$here/build/mrr}"
out="${1:-$(mktemp -d)}"
mkdir -p "$out"
source "$here/scripts/lib-sweep.sh"
scenes=("${sweep_scenes[@]}")
names=("mrr" "budget" "a priori" "+b0+c4+p0.15" "effect only")
methods=(mrr mrr-effect mrr-effect mrr-effect mrr-effect)
options=("" "" "--effect-budget 0" "--effect-budget 0 --effect-cap 4 --effect-posterior 0.15" "--effect-only")
effects=(ssao ssm ssgi)

columns=()
for n in "${names[@]}"; do
  for e in "${effects[@]}"; do columns+=("$n $e"); done
done
sweep_header "${columns[@]}"
failed=0
for scene in "${scenes[@]}"; do
  tag="${scene#builtin:}"
  row="| $scene |"
  for i in "${!names[@]}"; do
    log="$out/$tag-$i.log"
    # shellcheck disable=SC2086  # the options are words
    if "$mrr" compare --scene "$scene" --method "${methods[$i]}" --effect all --size 320x180 -q ${options[$i]} >"$log" 2>&1; then
      status=0
    else
      status=$?
    fi
    for e in "${effects[@]}"; do
      # compare prints "== compare SCENE, EFFECT, ..." before each effect's table, and its verdict
      # as a line starting "PASS" or "FAIL" after it
      v="$(awk -v e="$e" '/^== compare /{split($0, f, ", "); cur = f[2]} /^(PASS|FAIL)/{if (cur == e) {sub(/[: ].*/, ""); print}}' "$log" | tail -1)"
      [ -n "$v" ] || v="?"
      [ "$v" = PASS ] || failed=1
      row+=" $v |"
    done
    [ "$status" -eq 0 ] || failed=1
    echo "compare-effect-sweep: $scene ${names[$i]}: exit $status" >&2
  done
  echo "$row"
done
exit "$failed"
