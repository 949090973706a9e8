#!/usr/bin/env bash
# Installs the Debian 12 packages that radiosity needs, only those that are missing.
set -euo pipefail
packages=(cmake g++ make clang-format libopenmesh-dev libglm-dev libtinyobjloader-dev libstb-dev
          doctest-dev libbenchmark-dev nlohmann-json3-dev libpugixml-dev libcli11-dev
          libtinyexr-dev libtinygltf-dev
          # the programs' allocator (examples/allocator.cpp)
          libjemalloc-dev
          # the readers' fuzzers (clang's libFuzzer, scripts/fuzz.sh)
          clang libclang-rt-14-dev
          # the viewer (radiosity-view), and Xvfb with Mesa's software OpenGL for its tests
          pkg-config libglfw3-dev libepoxy-dev libimgui-dev xvfb xauth libgl1-mesa-dri
          # the distributed solve (-DRADIOSITY_WITH_MPI=ON) and its tests under mpirun
          libopenmpi-dev openmpi-bin)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "installing: ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
$sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq
$sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
