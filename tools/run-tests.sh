#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, runs every test.
# CI runs exactly this (.ci/run). Needs ../shared beside the repository (or
# PBRTC_SHARED_DIR); the tests that read it fail loudly without it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs"
# The libFuzzer targets need clang and ASan+UBSan: they get their own tree.
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPBRTC_FUZZ=ON \
  -DPBRTC_BUILD_TESTS=OFF -DPBRTC_BUILD_BENCHMARKS=OFF
cmake --build build-fuzz -j"$jobs" --target fuzz_targets
ctest --test-dir build --output-on-failure -j"$jobs"
