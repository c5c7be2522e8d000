#!/usr/bin/env bash
# The port stands on the frame contract alone (docs/architecture.md): no file under gpu/ includes a
# cpu_ref/ header, and CMake configures and builds the port's library (mrr_gpu, with common/
# and scenes/) with the oracle's targets absent (MRR_BUILD_ORACLE=OFF) and Embree's header
# poisoned (tests/no_embree/: an #error). Run by CTest as `port_builds_without_the_oracle`.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:?usage: test-port-alone.sh BUILD_DIR}"
if grep -n '#include "cpu_ref/' "$here"/gpu/*.h "$here"/gpu/*.cpp; then
  echo "FAIL: gpu/ includes cpu_ref/ headers (above)" >&2
  exit 1
fi
# Unoptimised and in batches (a unity build): what is proved is that it compiles without the
# oracle, and this way it takes a quarter of a Release build's time (40 s against 158 s).
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O0" -DCMAKE_UNITY_BUILD=ON \
  -DMRR_BUILD_ORACLE=OFF -DCMAKE_CXX_FLAGS="-I$here/tests/no_embree" >/dev/null
cmake --build "$build" --target mrr_gpu -j2
if grep -q 'mrr_cpu\|libembree' "$build/build.ninja"; then
  echo "FAIL: the port-only build still names the oracle or Embree" >&2
  exit 1
fi
echo "port_builds_without_the_oracle: mrr_gpu built with no oracle target and no Embree"
