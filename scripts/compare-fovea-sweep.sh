#!/usr/bin/env bash
# Checks that `mrr compare` passes with a gaze and with a previous frame on every built-in and
# shared scene (docs/figures.md, "Foveation and motion"): `mrr compare` on each scene at 320x180
# (SSAO, its default samples), for each method that docs/spec.md §13 limits, three ways:
#   gaze  --gaze 160,90 --ppd 10 (at 320x180 the default 67 ppd keeps the whole frame in the fovea;
#         at ppd 10 level 1 starts 81 px out and level 2 172 px out, so every term is exercised)
#   prev  --prev-frame F.json: F written by `render --frame-out` on the scene's own camera, then its
#         eye and target moved sideways by 2% of the viewing distance (the camera panned since)
#   pan   --pan X with the same X: the previous camera made from this one (no file)
# Prints a Markdown table (one row per scene, one cell per method and way: the verdict, the last
# line's first word) and exits 1 when any run is not PASS. Logs under OUT (default a temporary dir).
#   usage: scripts/compare-fovea-sweep.sh [OUT] [METHOD...]      (MRR=path/to/mrr to choose the binary)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mrr="${MRR:-$here/build/mrr}"
out="${1:-$(mktemp -d)}"
shift || true
methods=("$@")
[ ${#methods[@]} -gt 0 ] || methods=(mrr tiles mrr-effect)
mkdir -p "$out"
source "$here/scripts/lib-sweep.sh"
scenes=("${sweep_scenes[@]}")
size=320x180

columns=()
for m in "${methods[@]}"; do
  for way in gaze prev pan; do columns+=("$m $way"); done
done
sweep_header "${columns[@]}"
failed=0
for scene in "${scenes[@]}"; do
  tag="${scene#builtin:}"
  # The previous frame: the scene's own camera, moved sideways.
  "$mrr" render --scene "$scene" --size "$size" --samples 4 --frame-out "$out/$tag-this.json" -q 2>"$out/$tag-render.log"
  pan="$(python3 - "$out/$tag-this.json" "$out/$tag-prev.json" <<'EOF'
import json, math, sys
f = json.load(open(sys.argv[1]))
e, t, u = f["eye"], f["target"], f.get("up", [0, 1, 0])
d = [t[i] - e[i] for i in range(3)]
r = [d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]]
n = math.sqrt(sum(x * x for x in r))
step = 0.02 * math.sqrt(sum(x * x for x in d))
# The camera panned right by `step` since the previous frame: the previous one stood to the left.
f["eye"] = [e[i] - step * r[i] / n for i in range(3)]
f["target"] = [t[i] - step * r[i] / n for i in range(3)]
json.dump(f, open(sys.argv[2], "w"), indent=1)
print("%.6g" % step)
EOF
)"
  row="| $scene |"
  for m in "${methods[@]}"; do
    for way in gaze prev pan; do
      case "$way" in
        gaze) extra=(--gaze 160,90 --ppd 10) ;;
        prev) extra=(--prev-frame "$out/$tag-prev.json") ;;
        pan) extra=(--pan "$pan") ;;
      esac
      log="$out/$tag-$m-$way.txt"
      echo "[sweep] $scene $m $way" >&2
      if "$mrr" compare --scene "$scene" --size "$size" --method "$m" "${extra[@]}" -q >"$log" 2>"$log.err"; then :; fi
      verdict="$(tail -n 1 "$log" | cut -d: -f1)"
      [ -n "$verdict" ] || verdict="ERROR($(tail -n 1 "$log.err"))"
      [ "$verdict" = PASS ] || failed=1
      row+=" $verdict |"
    done
  done
  echo "$row"
done
exit $failed
