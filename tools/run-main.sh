#!/usr/bin/env bash
# The README's main command: installs what is missing, builds pbrt, and renders
# the bundled default scene (tools/default-scene/scene.pbrt) with it to
# build/default-scene.exr with a PNG preview beside it. pbrt compiles the scene
# (cached in $XDG_CACHE_HOME/pbrtc) and renders it in one step.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs" --target pbrt
./build/pbrt tools/default-scene/scene.pbrt --outfile build/default-scene.exr \
  --preview build/default-scene.png --stats
echo "main: wrote build/default-scene.exr and build/default-scene.png"
