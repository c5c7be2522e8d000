#!/usr/bin/env bash
# Fuzzes the glTF loader (tests/fuzz/gltf_fuzz.cpp) with libFuzzer + ASan + UBSan, built with
# clang in build-fuzz/. Usage: scripts/fuzz.sh [SECONDS] (default 60; CI runs 60). The seed
# corpus is written fresh from the built-in scenes; what the fuzzer learns accumulates in
# build-fuzz/corpus. A crash leaves build-fuzz/crash-* (or leak-*/timeout-*) and fails:
# turn each into a regression input under tests/fuzz/regressions/ (docs/hardening.md).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
bash "$here/scripts/install-deps.sh"
if ! command -v clang++ >/dev/null || ! dpkg-query -W -f='${Status}' libclang-rt-14-dev 2>/dev/null | grep -q "ok installed"; then
  echo "fuzz: installing clang and its fuzzer runtime" >&2
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends clang libclang-rt-14-dev >/dev/null
fi
build="$here/build-fuzz"
(cd "$here" && cmake --preset fuzz >/dev/null)  # CMakePresets.json: clang, MRR_FUZZ=ON
cmake --build "$build" -j"$(nproc)" --target gltf_fuzz fuzz_seeds
rm -rf "$build/seeds"
"$build/tests/fuzz/fuzz_seeds" "$build/seeds"
mkdir -p "$build/corpus"
# Every input that once crashed must stay fixed.
regressions=("$here"/tests/fuzz/regressions/*)
if [ -e "${regressions[0]}" ]; then
  echo "fuzz: replaying ${#regressions[@]} regression inputs" >&2
  "$build/tests/fuzz/gltf_fuzz" "${regressions[@]}"
fi
echo "fuzz: running for ${seconds} s" >&2
cd "$build"
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1
# libFuzzer's progress goes to fuzz.log; the summary (coverage, executions per second) and,
# on a finding, the report are printed.
status=0
./tests/fuzz/gltf_fuzz -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 -timeout=10 \
  -dict="$here/tests/fuzz/gltf.dict" -print_final_stats=1 corpus seeds >fuzz.log 2>&1 || status=$?
if [ "$status" -ne 0 ]; then
  tail -n 80 fuzz.log >&2
  echo "fuzz: FINDING (exit $status); the input is in $build (crash-*, leak-*, timeout-*, oom-*)" >&2
  exit "$status"
fi
grep -E "^#[0-9]+[[:space:]]+DONE" fuzz.log >&2 || true
grep -E "^stat::" fuzz.log >&2 || true
echo "fuzz: no finding in ${seconds} s ($(ls corpus | wc -l) inputs in the corpus)" >&2
