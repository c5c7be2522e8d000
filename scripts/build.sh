#!/usr/bin/env bash
# Installs the dependencies (Debian 12 packages) and builds mrr in Release into build/.
# Used by scripts/demo.sh, scripts/test.sh and .ci/run.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/install-deps.sh"
cmake -S "$here" -B "$here/build" -G Ninja -DCMAKE_BUILD_TYPE=Release ${MRR_CMAKE_ARGS:-} >/dev/null
cmake --build "$here/build" -j"$(nproc)"
