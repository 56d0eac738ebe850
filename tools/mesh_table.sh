#!/usr/bin/env bash
# tools/mesh_table.sh — the README's "Mesh sizes: PLY against Draco" table, on stdout.
#
# Runs build/mesh-table (tools/mesh/mesh_table_main.cpp; build it first, this script builds
# nothing) over every *.ply under the shared corpus's scenes/ and prints its Markdown table:
# binary PLY size against Draco at 11, 14 and 16 position bits, bits per vertex, the position
# error measured against the original vertices, and encode/decode times. Extra arguments go to
# mesh-table (--bits 12,14, --sequential). MESH_TABLE overrides the program's path.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
shared=${PBRTC_SHARED_DIR:-$repo/../shared}
program=${MESH_TABLE:-$repo/build/mesh-table}
if [[ ! -x $program ]]; then
  echo "mesh_table.sh: $program is not built (cmake --build build --target mesh-table)" >&2
  exit 1
fi
if [[ ! -d $shared/scenes ]]; then
  echo "mesh_table.sh: no scenes directory in $shared (set PBRTC_SHARED_DIR)" >&2
  exit 1
fi
# Sorted by path under C collation, so the table's order does not depend on the locale.
mapfile -d '' plys < <(find "$shared/scenes" -type f -name '*.ply' -print0 | LC_ALL=C sort -z)
if (( ${#plys[@]} == 0 )); then
  echo "mesh_table.sh: no .ply files under $shared/scenes" >&2
  exit 1
fi
exec "$program" --root "$shared/scenes" "$@" "${plys[@]}"
