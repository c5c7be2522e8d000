#!/usr/bin/env bash
# The oracle's unit and invariant tests under AddressSanitizer + UndefinedBehaviorSanitizer
# (leak checking on), in build-asan/. Any finding fails: UBSan does not recover. CI runs it
# after the README's test command.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/install-deps.sh"
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
cmake -S "$here" -B "$here/build-asan" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMRR_BUILD_BENCH=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$here/build-asan" -j"$(nproc)" --target common_tests oracle_tests
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
for t in common_tests oracle_tests; do
  echo "== $t under ASan+UBSan" >&2
  "$here/build-asan/tests/$t" --gtest_brief=1
done
