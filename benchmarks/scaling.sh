#!/usr/bin/env bash
# The distributed solve's scaling table: bench_distributed under mpirun on 1, 2 and 4 ranks
# (more ranks than cores share them: --oversubscribe), one OpenMP thread per rank so that the
# ranks alone divide the work.
#   benchmarks/scaling.sh BUILD_DIR [million|room3]
set -euo pipefail
build=${1:-build} scene=${2:-million}
export OMP_NUM_THREADS=1
echo "$(nproc) cores; $(uptime)"
for n in 1 2 4; do
  header=""
  [ "$n" -eq 1 ] && header=1
  BENCH_HEADER=$header mpirun --oversubscribe -np "$n" "$build/benchmarks/bench_distributed" "$scene"
done
