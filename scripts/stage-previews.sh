#!/usr/bin/env bash
# PNG previews of a --stages EXR: every level's stencil, alpha and sub-image scaled up to
# full size (nearest), the edge kinds as colours, and the level map. Usage: STAGES.exr OUTDIR
set -euo pipefail
stages="$1"; out="$2"
mkdir -p "$out"
size=$(oiiotool --info "$stages" | head -1 | sed -E 's/.*: *([0-9]+) x +([0-9]+).*/\1x\2/')
info=$(oiiotool -a --info -v "$stages")
part() { [[ "$info" == *"name: \"$1\""* ]]; }
# Edges: red = normal, green = depth (yellow = both), blue = background; for SSM blue is the
# shadow edges instead, as in the paper's Fig. 1.
if [[ "$info" == *"shadow"* ]] && oiiotool "$stages" --subimage edges --ch normal,depth,shadow -d uint8 -o "$out/edges.png" 2>/dev/null; then
  :
else
  oiiotool "$stages" --subimage edges --ch normal,depth,background -d uint8 -o "$out/edges.png"
fi
# Effect images: SSGI's indirect light is RGB and dim, shown ×GAIN (default 4).
gain="${GAIN:-4}"
# A level part is stored at its own size inside the full display window: make the data
# window the display window, then scale it up with nearest-neighbour so pixels stay visible.
grey() { oiiotool "$stages" --subimage "$1" --ch "$2,$2,$2" --fullpixels --resize:filter=box "$size" "${@:4}" -d uint8 -o "$3"; }
for l in 0 1 2 3; do
  part "stencil.L$l" || continue
  grey "stencil.L$l" S "$out/stencil_L$l.png"
  grey "alpha.L$l" a "$out/alpha_L$l.png" --clamp:min=0:max=1
  if [[ "$info" == *"c_raw.R"* ]]; then
    oiiotool "$stages" --subimage "raw.L$l" --ch c_raw.R,c_raw.G,c_raw.B --fullpixels --resize:filter=box "$size" \
      --mulc "$gain" --clamp:min=0:max=1 -d uint8 -o "$out/sub_L$l.png"
  else
    grey "raw.L$l" c_raw "$out/sub_L$l.png"
  fi
done
# The finest contributing level at each pixel (viridis): 0 full = purple, 1 = blue,
# 2 = green, 3 eighth = yellow.
oiiotool "$stages" --subimage levelmap --mulc 0.3333 --colormap viridis -d uint8 -o "$out/levelmap.png"
