#!/usr/bin/env bash
# The README's main command: installs what is missing, builds, compiles the
# bundled default scene (tools/default-scene/scene.pbrt) to an archive and
# renders it to build/default-scene.exr with a PNG preview beside it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs" --target pbrtc pbrtrun
./build/pbrtc tools/default-scene/scene.pbrt -o build/default-scene.pbrta
./build/pbrtrun build/default-scene.pbrta --outfile build/default-scene.exr \
  --preview build/default-scene.png --stats
echo "main: wrote build/default-scene.exr and build/default-scene.png"
