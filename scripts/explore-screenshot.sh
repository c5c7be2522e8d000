#!/usr/bin/env bash
# Refreshes docs/images/explore.png: `mrr explore` on the arcade (builtin:demo without the shared
# scenes) in headless Chromium, driven by the page's browser test.
#   scripts/explore-screenshot.sh [path/to/mrr]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mrr="${1:-$here/build/mrr}"
scenes="${MRR_SCENES_DIR:-$here/../shared/scenes}"
scene=builtin:demo
[ -f "$scenes/sascha-arcade/subpass_scene_opaque.gltf" ] && scene=arcade
MRR_EXPLORE_SCENE="$scene" MRR_EXPLORE_SCREENSHOT="$here/docs/images/explore.png" \
  /usr/bin/python3 "$here/tests/explore/test_explore_browser.py" "$mrr"
