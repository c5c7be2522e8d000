#!/usr/bin/env bash
# The sanitizer builds (docs/hardening.md). Any finding fails: UBSan does not recover, ASan
# and TSan exit non-zero. CI runs this after the README's test command.
#  1. ASan + UBSan (build-asan/, leak checking on): the unit and oracle tests, then a small
#     render of every built-in scene with every effect on both paths (cpu and gpu: the GL
#     port on llvmpipe, when an EGL device is there).
#  2. TSan (build-tsan/): the oracle's threaded stages at 1, 2 and 8 threads, every effect
#     (the thread-count determinism tests). Suppressions, each with its reason, are in
#     tests/tsan.supp and tests/lsan.supp; none matches a frame of mrr's own code.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/install-deps.sh"
jobs="$(nproc)"

echo "== ASan+UBSan build" >&2
(cd "$here" && cmake --preset asan >/dev/null)  # CMakePresets.json: MRR_SANITIZE=address
cmake --build "$here/build-asan" -j"$jobs" --target common_tests oracle_tests mrr
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
export LSAN_OPTIONS="suppressions=$here/tests/lsan.supp:print_suppressions=0"
for t in common_tests oracle_tests; do
  echo "== $t under ASan+UBSan" >&2
  "$here/build-asan/tests/$t" --gtest_brief=1
done
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
mrr="$here/build-asan/mrr"
# On the gpu path, leak checking is off (ASan's and UBSan's other checks stay on): Mesa's
# driver, which glvnd dlopens, leaks 112 bytes of its own and is dlclosed at exit, after
# which LeakSanitizer can no longer name the module to suppress it. mrr's own code is
# leak-checked on the cpu path and in the unit tests above, and the GL objects the port
# creates are freed by RAII wrappers those tests exercise.
gpuAsan="detect_leaks=0:abort_on_error=1"
paths=(cpu)
if ASAN_OPTIONS="$gpuAsan" "$mrr" render --scene builtin:plane --path gpu --size 8x8 --samples 1 -q \
     --out "$scratch/probe.exr" 2>/dev/null; then
  paths+=(gpu)
elif [ "${MRR_REQUIRE_GL:-0}" = 1 ]; then
  echo "test-sanitizers: no EGL device for the gpu path (MRR_REQUIRE_GL=1)" >&2
  ASAN_OPTIONS="$gpuAsan" "$mrr" render --scene builtin:plane --path gpu --size 8x8 --samples 1 -q \
    --out "$scratch/probe.exr"
  exit 1
fi
# Every built-in, as the unknown-scene error lists them ("expected one of demo, plane, ...").
scenes=$("$mrr" render --scene builtin:none --out "$scratch/none.exr" 2>&1 |
  sed -n 's/.*expected one of \([a-z, ]*\)).*/\1/p' | tr -d ',' | tr ' ' '\n' | sed 's/^/builtin:/' | grep -v '^builtin:$' || true)
if [ "$(echo "$scenes" | wc -w)" -lt 10 ]; then
  echo "test-sanitizers: could not list the built-in scenes (got: $scenes)" >&2
  exit 1
fi
# One render per scene, effect and path, $jobs at a time (each is one process, mostly the
# sanitizers' own start-up); a failing one's whole log is printed, then the script fails.
renderUnderAsan() {
  local scene="$1" effect="$2" path="$3" options="$ASAN_OPTIONS"
  local name="$path-${scene#builtin:}-$effect"
  [ "$path" = gpu ] && options="$gpuAsan"
  if ! ASAN_OPTIONS="$options" "$mrr" render --scene "$scene" --effect "$effect" --path "$path" --size 48x32 \
       --samples 4 --shadow-map-size 256 -q --out "$scratch/$name.exr" --stages "$scratch/$name.stages.exr" \
       --report "$scratch/$name.json" >"$scratch/$name.log" 2>&1; then
    echo "== render $scene $effect --path $path under ASan+UBSan FAILED:" >&2
    cat "$scratch/$name.log" >&2
    return 1
  fi
  echo "== render $scene $effect --path $path under ASan+UBSan: clean" >&2
}
export -f renderUnderAsan
export mrr scratch gpuAsan
for path in "${paths[@]}"; do
  for scene in $scenes; do
    for effect in ssao ssm ssgi; do echo "$scene $effect $path"; done
  done
done | xargs -P "$jobs" -n 3 bash -c 'renderUnderAsan "$@"' _
if [[ " ${paths[*]} " == *" gpu "* ]]; then
  echo "== compare (every stage, HTML report) and probe --path both under ASan+UBSan" >&2
  ASAN_OPTIONS="$gpuAsan" "$mrr" compare --scene builtin:demo --effect all --size 48x32 --samples 4 \
    --shadow-map-size 256 -q --report "$scratch" >/dev/null
  ASAN_OPTIONS="$gpuAsan" "$mrr" probe --path both --scene builtin:demo --size 48x32 --samples 4 -q \
    --pixel 20,10 >/dev/null
fi

echo "== TSan build" >&2
(cd "$here" && cmake --preset tsan >/dev/null)  # CMakePresets.json: MRR_SANITIZE=thread
cmake --build "$here/build-tsan" -j"$jobs" --target oracle_thread_tests planted_race
echo "== TSan must report the planted race" >&2
if TSAN_OPTIONS="halt_on_error=1" "$here/build-tsan/tests/planted_race" >"$scratch/race.txt" 2>&1 ||
  ! grep -q "ThreadSanitizer: data race" "$scratch/race.txt"; then
  cat "$scratch/race.txt" >&2
  echo "test-sanitizers: TSan did not report the planted race in tests/sanitizers/planted_race.cpp" >&2
  exit 1
fi
echo "== oracle threads (1, 2, 8) under TSan" >&2
TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$here/tests/tsan.supp" \
  "$here/build-tsan/tests/oracle_thread_tests" --gtest_brief=1 --gtest_filter='*OneTwoAndEightThreads*'
echo "test-sanitizers: clean" >&2
