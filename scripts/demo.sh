#!/usr/bin/env bash
# Installs dependencies, builds Penumbra (release preset) and runs the main job on a bundled scene:
# an exact soft-shadow image of the office desk (every pixel's direct irradiance by the exact
# reference), written to out/desk-475-raytrace.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
mkdir -p out
scene=scenes/office-desk/desk-475.json
build/bin/penumbra info "$scene"
build/bin/penumbra render "$scene" --method raytrace --size 640x480 -o out/desk-475-raytrace.png
echo "wrote $(pwd)/out/desk-475-raytrace.png"
