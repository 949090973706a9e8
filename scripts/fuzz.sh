#!/usr/bin/env bash
# Builds the readers' libFuzzer harnesses (clang, AddressSanitizer + UndefinedBehaviorSanitizer)
# in their own build folder and runs each for a bounded time, from the committed seed corpus
# (tests/fuzz/corpus) and the built-in scenes (fuzz_seeds). Exits non-zero on a finding; the
# input that caused it is kept in $build/findings/. Usage: scripts/fuzz.sh [seconds per harness]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-${RADIOSITY_FUZZ_SECONDS:-20}}
build=${RADIOSITY_FUZZ_BUILD_DIR:-build-fuzz}
launcher=()
if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
  -DRADIOSITY_BUILD_FUZZERS=ON -DRADIOSITY_BUILD_TESTS=OFF -DRADIOSITY_BUILD_EXAMPLES=OFF \
  -DRADIOSITY_BUILD_BENCHMARKS=OFF -DRADIOSITY_OPENMP=OFF -DRADIOSITY_WERROR=ON "${launcher[@]}" \
  > /dev/null
cmake --build "$build" -j "$(nproc)"
mkdir -p "$build/findings"
for reader in obj rrv gltf; do
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
