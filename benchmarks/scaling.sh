#!/usr/bin/env bash
# The distributed solve's scaling table: bench_distributed under mpirun on 1, 2 and 4 ranks
# (more ranks than cores share them: --oversubscribe), one OpenMP thread per rank so that the
# ranks alone divide the work; first, side by side, one rank with a thread per core (what the
# program does as one process).
#   benchmarks/scaling.sh BUILD_DIR [million|room3]
set -euo pipefail
build=${1:-build} scene=${2:-million}
echo "$(nproc) cores; $(uptime)"
# (mpirun binds each rank to a core unless told not to: the threads need them all.)
BENCH_HEADER=1 OMP_NUM_THREADS=$(nproc) mpirun --bind-to none -np 1 "$build/benchmarks/bench_distributed" "$scene"
for n in 1 2 4; do
  OMP_NUM_THREADS=1 mpirun --oversubscribe -np "$n" "$build/benchmarks/bench_distributed" "$scene"
done
