#!/usr/bin/env bash
# Installs the dependencies (Debian 12 packages) and builds mrr in Release into build/.
#   bash scripts/build.sh              every target: mrr, the tests, the stage benchmark
#   bash scripts/build.sh mrr [T...]   only the named targets and what they need
#                                      (scripts/demo.sh builds `mrr` alone: no test binary)
# Used by scripts/demo.sh, scripts/test.sh and .ci/run. A unity build (CMake's CMAKE_UNITY_BUILD:
# a target's sources compiled a batch at a time) halves a fresh build on 2 cores (docs/platform.md);
# MRR_UNITY_BUILD=OFF builds one file at a time, which suits edit-and-rebuild work.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/install-deps.sh"
cmake -S "$here" -B "$here/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_UNITY_BUILD="${MRR_UNITY_BUILD:-ON}" ${MRR_CMAKE_ARGS:-} >/dev/null
if [ $# -gt 0 ]; then
  cmake --build "$here/build" -j"$(nproc)" --target "$@"
else
  cmake --build "$here/build" -j"$(nproc)"
fi
