#!/usr/bin/env bash
# The README's main job: on the built-in demo scene, render the method (multires) and the
# full-resolution reference with the CPU oracle, compare them, and write everything to
# out/demo/: final and shaded images, every stage (multi-part EXR and PNG previews), the JSON
# report with error figures, and a probe of one pixel; the same frame through the GL port, and
# `mrr compare` of every stage of all three effects (table and HTML report); then SSM and
# SSGI in out/demo/ssm/ and out/demo/ssgi/. Needs nothing outside the repo.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/build.sh" mrr  # the demo runs mrr alone: no test binary is built
mrr="$here/build/mrr"
out="${1:-$here/out/demo}"
size="${MRR_DEMO_SIZE:-1280x720}"
mkdir -p "$out"
common=(--scene builtin:demo --effect ssao --size "$size" --samples 64)
echo "== multires (the method) and full (the reference), compared" >&2
"$mrr" render "${common[@]}" --method mrr --reference \
  --out "$out/final.exr" --shaded "$out/shaded.png" --stages "$out/stages.exr" --report "$out/report.json"
"$mrr" render "${common[@]}" --method full --quiet --out "$out/reference.exr" --shaded "$out/reference_shaded.png"
"$mrr" render "${common[@]}" --method mrr --quiet --out "$out/final.png"
"$mrr" render "${common[@]}" --method full --quiet --out "$out/reference.png"
bash "$here/scripts/stage-previews.sh" "$out/stages.exr" "$out"
# The port: the same frame through OpenGL 3.3 (headless EGL; Mesa's llvmpipe here), then the
# oracle against the port on every stage of all three effects (mrr compare, docs/compare.md):
# the table in cpu_vs_gpu.txt, the HTML report in $out/compare/index.html.
if "$mrr" render "${common[@]}" --path gpu --method mrr --quiet --out "$out/gpu_final.exr" \
     --stages "$out/gpu_stages.exr" --report "$out/gpu_report.json" 2> "$out/gpu_error.txt"; then
  rm -f "$out/gpu_error.txt"
  echo "== oracle vs port, every stage of ssao, ssm and ssgi (mrr compare)" >&2
  mkdir -p "$out/compare"
  status=0
  "$mrr" compare --scene builtin:demo --effect all --size "$size" --quiet --report "$out/compare" \
    > "$out/cpu_vs_gpu.txt" || status=$?
  grep -E "^(== compare|PASS|FAIL)" "$out/cpu_vs_gpu.txt" | sed 's/; oracle.*//' >&2
  [ "$status" -le 1 ] || exit "$status"
else
  echo "== no GL port run: $(cat "$out/gpu_error.txt")" >&2
fi
# The difference, scaled ×10 so it can be seen.
oiiotool "$out/final.exr" "$out/reference.exr" --absdiff --mulc 10 --clamp:min=0:max=1 -d uint8 -o "$out/difference_x10.png"
w="${size%x*}"; h="${size#*x}"
"$mrr" probe "${common[@]}" --quiet --pixel "$((w / 2)),$((h / 2))" > "$out/probe_center.txt"
# The paper's other two effects on the same scene, each in its own folder.
for e in ssm ssgi; do
  echo "== $e" >&2
  mkdir -p "$out/$e"
  "$mrr" render --scene builtin:demo --effect "$e" --size "$size" --method mrr --reference --quiet \
    --out "$out/$e/final.exr" --shaded "$out/$e/shaded.png" --stages "$out/$e/stages.exr" --report "$out/$e/report.json"
  bash "$here/scripts/stage-previews.sh" "$out/$e/stages.exr" "$out/$e"
  python3 -c "import json,sys; r=json.load(open(sys.argv[1])); e=r['error_vs_full']; print(f\"{r['effect']}-{r['samples']}: ideal speedup {r['ideal_speedup']:.2f}x (on geometry {r['ideal_speedup_hit']:.2f}x), RMS vs full {e['rms']:.5f}, SSIM {e['ssim']:.4f}\")" "$out/$e/report.json"
done
echo "== report: $out/report.json" >&2
python3 - "$out/report.json" <<'PY' || cat "$out/report.json"
import json, sys
r = json.load(open(sys.argv[1]))
e = r["error_vs_full"]
print(f"scene {r['scene']}  {r['width']}x{r['height']}  ssao-{r['samples']}  threads {r['threads']}")
for l in r["levels"]:
    print(f"  level {l['level']} (1/{l['scale']}): shaded {l['shaded_pixels']} pixels")
print(f"ideal speedup {r['ideal_speedup']:.2f}x (on geometry {r['ideal_speedup_hit']:.2f}x)   frame {r['timings_ms']['total']:.0f} ms, one run")
print(f"vs full: RMS {e['rms']:.5f}  PSNR {e['psnr']:.1f} dB  SSIM {e['ssim']:.4f}  max {e['max_abs']:.4f}  edge-band RMS {e['edge_band_rms']:.5f}")
PY
echo "== wrote $(ls "$out" | wc -l) files to $out" >&2
