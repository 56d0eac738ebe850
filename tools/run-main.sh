#!/usr/bin/env bash
# The README's main command: installs what is missing, builds, and runs the main
# job on the bundled default scene (tools/default-scene/scene.pbrt).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs" --target pbrtc
./build/pbrtc --check tools/default-scene/scene.pbrt
