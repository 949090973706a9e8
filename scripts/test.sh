#!/usr/bin/env bash
# The README's test command: installs what is missing, builds every target with warnings as
# errors, the distributed solve included (MPI), and runs the whole suite (one ctest test per
# doctest case, and the mpirun tests).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
build=${RADIOSITY_BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRADIOSITY_WERROR=ON -DRADIOSITY_WITH_MPI=ON \
  ${RADIOSITY_CMAKE_ARGS:-}
cmake --build "$build" -j "$(nproc)"
ctest --test-dir "$build" --output-on-failure -j "$(nproc)"
