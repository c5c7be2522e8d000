#!/usr/bin/env bash
# Regenerates every image in docs/images from mrr's own output (the README's stage picture,
# the method walk-through in docs/method.md, and the shared scenes in docs/scenes.md).
# Usage: [MRR=path/to/mrr] scripts/make-doc-images.sh   (after scripts/build.sh; needs ../shared/scenes for the
# scene thumbnails, and fonts-dejavu-core for the labels)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mrr="${MRR:-$here/build/mrr}"  # MRR: another binary (a copy, while build/ is rebuilt)
img="$here/docs/images"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$img"
font=/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf
label() {  # label IN OUT TEXT
  if [ -f "$font" ]; then
    oiiotool "$1" --ch R,G,B --text:x=12:y=34:size=26:color=1,0.9,0.2:font="$font" "$3" -o "$2"
  else
    cp "$1" "$2"
  fi
}
echo "[docs] demo scene stages" >&2
common=(--scene builtin:demo --size 640x360 --samples 64 --quiet)
"$mrr" render "${common[@]}" --out "$work/final.exr" --shaded "$work/shaded.png" --stages "$work/stages.exr"
"$mrr" render "${common[@]}" --method full --out "$work/reference.exr"
bash "$here/scripts/stage-previews.sh" "$work/stages.exr" "$work"
for f in final reference; do oiiotool "$work/$f.exr" --ch Y,Y,Y -d uint8 -o "$work/$f.png"; done
oiiotool "$work/final.exr" "$work/reference.exr" --absdiff --mulc 10 --clamp:min=0:max=1 --ch Y,Y,Y -d uint8 -o "$work/diff.png"
label "$work/shaded.png" "$work/l1.png" "scene (shaded)"
label "$work/edges.png" "$work/l2.png" "1 edges: normal depth background"
label "$work/levelmap.png" "$work/l3.png" "2 finest level per pixel"
label "$work/stencil_L0.png" "$work/l4.png" "3 stencil S0 (full res)"
label "$work/stencil_L2.png" "$work/l5.png" "3 stencil S2 (1/4 res)"
label "$work/sub_L0.png" "$work/l6.png" "4 sub-image c0 (full res)"
label "$work/sub_L3.png" "$work/l7.png" "4 sub-image c3 (1/8 res)"
label "$work/final.png" "$work/l8.png" "5 blended result"
label "$work/diff.png" "$work/l9.png" "|result - full| x10"
oiiotool "$work"/l{1,2,3,4,5,6,7,8,9}.png --mosaic:pad=4 3x3 -d uint8 -o "$img/pipeline.png"
for f in shaded edges levelmap stencil_L0 stencil_L1 stencil_L2 stencil_L3 alpha_L0 alpha_L1 alpha_L2 sub_L0 sub_L1 sub_L2 sub_L3 final reference diff; do
  cp "$work/$f.png" "$img/demo_$f.png"
done
# SSM and SSGI on the apartment: the same nine pictures per effect.
effect_mosaic() {  # effect samples gain
  local e="$1" n="$2" g="$3" d="$work/$1"
  mkdir -p "$d"
  local c=(--scene apartment --effect "$e" --samples "$n" --size 640x360 --quiet)
  "$mrr" render "${c[@]}" --out "$d/final.exr" --shaded "$d/shaded.png" --stages "$d/stages.exr"
  "$mrr" render "${c[@]}" --method full --out "$d/reference.exr"
  GAIN="$g" bash "$here/scripts/stage-previews.sh" "$d/stages.exr" "$d" >/dev/null
  local ch=Y,Y,Y
  [ "$e" = ssgi ] && ch=R,G,B
  oiiotool "$d/final.exr" --ch "$ch" --mulc "$g" --clamp:min=0:max=1 -d uint8 -o "$d/final.png"
  oiiotool "$d/reference.exr" --ch "$ch" --mulc "$g" --clamp:min=0:max=1 -d uint8 -o "$d/reference.png"
  oiiotool "$d/final.exr" "$d/reference.exr" --absdiff --ch "$ch" --mulc 10 --clamp:min=0:max=1 -d uint8 -o "$d/diff.png"
  local edges="1 edges: normal depth background"
  [ "$e" = ssm ] && edges="1 edges: normal depth shadow"
  label "$d/shaded.png" "$d/l1.png" "$e: scene (shaded)"
  label "$d/edges.png" "$d/l2.png" "$edges"
  label "$d/levelmap.png" "$d/l3.png" "2 finest level per pixel"
  label "$d/stencil_L0.png" "$d/l4.png" "3 stencil S0 (full res)"
  label "$d/sub_L0.png" "$d/l5.png" "4 sub-image c0 (full res)"
  label "$d/sub_L3.png" "$d/l6.png" "4 sub-image c3 (1/8 res)"
  label "$d/final.png" "$d/l7.png" "5 blended result"
  label "$d/reference.png" "$d/l8.png" "full resolution"
  label "$d/diff.png" "$d/l9.png" "|result - full| x10"
  oiiotool "$d"/l{1,2,3,4,5,6,7,8,9}.png --mosaic:pad=4 3x3 -d uint8 -o "$img/pipeline_$e.png"
}
if [ -d "${MRR_SCENES_DIR:-$here/../shared/scenes}" ]; then
  echo "[docs] apartment ssm, ssgi" >&2
  effect_mosaic ssm 196 1
  effect_mosaic ssgi 288 4
  for s in cornell arcade apartment; do
    echo "[docs] $s" >&2
    "$mrr" render --scene "$s" --size 640x360 --samples 64 --quiet --shaded "$work/$s.png" --out "$work/${s}_ao.png" \
      --stages "$work/${s}_stages.exr"
    bash "$here/scripts/stage-previews.sh" "$work/${s}_stages.exr" "$work/${s}_prev" >/dev/null
    oiiotool "$work/$s.png" "$work/${s}_ao.png" --ch 0,0,0 "$work/${s}_prev/edges.png" "$work/${s}_prev/levelmap.png" \
      --mosaic:pad=4 4x1 --resize 1280x0 -d uint8 -o "$img/scene_$s.png" 2>/dev/null || \
    oiiotool "$work/$s.png" "$work/${s}_prev/edges.png" "$work/${s}_prev/levelmap.png" --mosaic:pad=4 3x1 -d uint8 -o "$img/scene_$s.png"
  done
fi
if [ -d "${MRR_SCENES_DIR:-$here/../shared/scenes}" ]; then
  # The automatic SSAO radius before and after the view-framed default (docs/scenes.md): made by matplotlib.
  echo "[docs] ao-before-after" >&2
  MRR="$mrr" /usr/bin/python3 "$here/scripts/ao-before-after.py" "$img/ao-before-after.png" \
    builtin:demo cornell arcade apartment
fi
echo "[docs] wrote $(ls "$img" | wc -l) images to $img" >&2
