#!/usr/bin/env bash
# The readers under AddressSanitizer and UndefinedBehaviorSanitizer, in their own build folder:
# first the suite's fuzz tests (test_fuzz_structured's hostile scenes, test_fuzz's byte
# mutations), then each libFuzzer harness for a bounded time, from the committed seed corpus
# (tests/fuzz/corpus) and the built-in scenes (fuzz_seeds). libFuzzer is clang's: without
# clang++ the harnesses are skipped with a message and the tests run under the default compiler.
# Exits non-zero on a finding; the input that caused it is kept in $build/findings/.
# Usage: scripts/fuzz.sh [seconds per harness]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-${RADIOSITY_FUZZ_SECONDS:-20}}
build=${RADIOSITY_FUZZ_BUILD_DIR:-build-fuzz}
tests=(test_fuzz_structured test_fuzz)
readers=(obj rrv gltf)
if command -v clang++ > /dev/null; then
  cxx=clang++
  fuzzers=ON
else
  cxx=${CXX:-c++}
  fuzzers=OFF
  echo "fuzz.sh: clang++ not found, so the libFuzzer harnesses are skipped" \
    "(scripts/install_deps.sh installs clang and libclang-rt-14-dev)" >&2
fi
launcher=()
if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
# Debug keeps the assertions; -O1 makes sanitized code fast enough to run many inputs.
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" -DRADIOSITY_SANITIZE=address,undefined \
  -DRADIOSITY_BUILD_FUZZERS=$fuzzers -DRADIOSITY_BUILD_TESTS=ON -DRADIOSITY_BUILD_EXAMPLES=OFF \
  -DRADIOSITY_BUILD_BENCHMARKS=OFF -DRADIOSITY_OPENMP=OFF -DRADIOSITY_WERROR=ON "${launcher[@]}" \
  > /dev/null
# fuzz_programs: the tests and, with clang, fuzz_seeds and the harnesses, built side by side.
cmake --build "$build" -j "$(nproc)" --target fuzz_programs
for t in "${tests[@]}"; do
  echo "== $t under ASan + UBSan ($cxx)"
  "$build/tests/$t"
done
[ $fuzzers = ON ] || exit 0
# The harnesses write each input to files (the readers take paths): in memory if there is room.
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
mkdir -p "$build/findings"
for reader in "${readers[@]}"; do
  echo "== fuzz_$reader: $seconds s"
  corpus="$build/corpus/$reader"  # grows from run to run; the committed seeds stay as they are
  "$build/tests/fuzz/fuzz_seeds" "$corpus" "$reader"
  # -timeout: one input may take at most 10 s; -rss_limit_mb: and at most 2 GB.
  log="$build/fuzz_$reader.log"
  if ! "$build/tests/fuzz/fuzz_$reader" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -max_len=16384 -dict="tests/fuzz/$reader.dict" -print_final_stats=1 \
    -artifact_prefix="$build/findings/$reader-" "$corpus" "tests/fuzz/corpus/$reader" \
    > "$log" 2>&1; then
    tail -n 60 "$log"
    echo "fuzz_$reader: a finding (the input is in $build/findings/, the log in $log)" >&2
    exit 1
  fi
  grep -E "^(Done|stat::number_of_executed_units|stat::peak_rss_mb)" "$log" || tail -n 5 "$log"
done
