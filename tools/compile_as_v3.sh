#!/usr/bin/env bash
# Compiles a shared scene as pbrt-v3 sees it (scenes.txt's "v3-no-hdr" column): pbrt-v3 cannot
# read .hdr maps and renders such an infinite light as its constant L, which is the scene
# without the map. The text is piped to pbrtc from the scene's directory, so relative paths
# still resolve; everything else in the scene is checked as usual. Used by tools/convergence.sh
# (the image pbrt-v3's reference shows) and tools/render_bench.sh (the same work side by side).
#
#   tools/compile_as_v3.sh PBRTC SCENE ARCHIVE
set -euo pipefail
pbrtc="$1" scene="$2" archive="$3"
cd "$(dirname "$scene")"
sed -E 's/"string mapname" *\[? *"[^"]*\.hdr" *\]?//' "$(basename "$scene")" |
  "$pbrtc" -q - -o "$archive"
