#!/usr/bin/env bash
# The README's test command: installs what it needs, builds in Release, runs every test.
# The shared glTF scenes are read from ../shared/scenes (override: MRR_SCENES_DIR).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/install-deps.sh" test
bash "$here/scripts/build.sh"
ctest --test-dir "$here/build" --output-on-failure -j"$(nproc)" "$@"
