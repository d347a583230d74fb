#!/usr/bin/env bash
# Installs every build, test and tool dependency of Penumbra from Debian 12 packages.
# Idempotent: re-running it only checks that everything is present.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config clang-format
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libpolyclipping-dev
  libjemalloc-dev  # the programs' allocator (CMakeLists.txt: PENUMBRA_JEMALLOC)
  libembree-dev libtbb-dev
  nlohmann-json3-dev libtinyobjloader-dev libtinygltf-dev libstb-dev
  libcli11-dev
  libegl-dev libegl-mesa0 libgl1-mesa-dri libopengl-dev libgl-dev python3-glad
  libglfw3-dev libimgui-dev
  libopenexr-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-14-dev llvm  # the fuzz targets: libFuzzer, and llvm-symbolizer for their stacks
  xvfb xauth
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
echo "install-deps: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
