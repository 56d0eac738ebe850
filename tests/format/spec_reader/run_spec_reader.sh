#!/usr/bin/env bash
# Compiles real shared scenes with the built pbrtc, in each codec, and every shared entry scene,
# and reads every archive with read_pbrta.py: a reader written from format/ARCHIVE.md and
# SCHEMA.md alone, which must check each archive as the spec says and print the same summary as
# `pbrtc --info`. Then damaged copies must be refused. A format change that the spec does not describe fails here.
# Usage: run_spec_reader.sh PBRTC SHARED_DIR SOURCE_DIR SCRATCH_DIR
set -euo pipefail
pbrtc=$1 shared=$2 source=$3 work=$4
reader="$source/tests/format/spec_reader/read_pbrta.py"
schema="$source/format/SCHEMA.md"
if [ ! -d "$shared/scenes" ]; then
  echo "FAIL: shared corpus not found at $shared (set PBRTC_SHARED_DIR)" >&2
  exit 1
fi
rm -rf "$work" && mkdir -p "$work"
s="$shared/scenes"
compile() {  # compile NAME SCENE [pbrtc options...]
  local name=$1 scene=$2
  shift 2
  "$pbrtc" -q --nthreads 2 "$@" "$scene" -o "$work/$name.pbrta"
}
compile cornell "$s/rs-cornell-box/cornell_box.pbrt"
compile cornell_none "$s/rs-cornell-box/cornell_box.pbrt" --codec none
compile caustic "$s/v3-caustic-glass-sppm/f16-11a.pbrt"
compile killeroo_draco "$s/v3-killeroo-simple/killeroo-simple.pbrt" --draco-bits 14
compile mappings "$s/hm-textures/pbrt-v3-rs/scenes/textures/2d-mappings.pbrt"
compile mappings_none "$s/hm-textures/pbrt-v3-rs/scenes/textures/2d-mappings.pbrt" --codec none
compile mappings_f16 "$s/hm-textures/pbrt-v3-rs/scenes/textures/2d-mappings.pbrt" \
  --texture-precision f16
compile envmap "$s/v3-figures/f8-22.pbrt"
compile subsurface "$s/v3-figures/f11-15.pbrt"
compile anim "$s/rs-anim-bluespheres/anim-bluespheres.pbrt"
compile instances "$s/hm-instances/pbrt-v3-rs/scenes/objects/instances.pbrt"

# Its 4 MB of texels are one raw section of several 1 MiB checksum chunks.
"$pbrtc" --info "$work/mappings_none.pbrta" >"$work/mappings_none.txt"
if ! grep -q "texels *raw .*MiB" "$work/mappings_none.txt"; then
  echo "FAIL: mappings_none.pbrta has no raw texels section of several chunks to read" >&2
  exit 1
fi
# Its 2 MiB of geometry cost little more in 1 MiB frames: shuffled frames of both sizes are read.
python3 "$reader" -v --schema "$schema" "$work/caustic.pbrta" >"$work/caustic.txt"
if ! grep -q "geometry: zstd, [0-9]* frames of 1048576 bytes, shuffled" "$work/caustic.txt"; then
  echo "FAIL: caustic.pbrta has no geometry section in 1 MiB shuffled frames to read" >&2
  exit 1
fi
python3 "$reader" --schema "$schema" --pbrtc "$pbrtc" "$work"/*.pbrta

# Every entry scene of the shared corpus that compiles (a few name files the corpus lacks): the
# reader reads each archive, as pbrtc --info describes it.
mkdir -p "$work/all"
compiled=0
while IFS= read -r scene; do
  name=$(basename "$(dirname "$scene")")_$(basename "$scene" .pbrt)
  if "$pbrtc" -q --nthreads 2 "$scene" -o "$work/all/$name.pbrta" 2>/dev/null; then
    compiled=$((compiled + 1))
  fi
done < <(grep -rl --include='*.pbrt' WorldBegin "$s" | sort)
if [ "$compiled" -lt 60 ]; then
  echo "FAIL: only $compiled shared scenes compiled (expected 60 or more)" >&2
  exit 1
fi
python3 "$reader" --schema "$schema" --pbrtc "$pbrtc" "$work"/all/*.pbrta | tail -n 1
echo "read the archives of $compiled shared scenes"

# Damaged copies: a byte in the middle of the file, the header, a truncation. The reader and
# pbrtc --verify must both refuse each, the reader with an error line and no traceback.
damage() {  # damage NAME SOURCE OFFSET_EXPR | truncate
  python3 - "$@" <<'PY'
import sys
name, src, how = sys.argv[1:4]
b = bytearray(open(src, 'rb').read())
if how == 'truncate':
    b = b[:len(b) * 2 // 3]
else:
    at = {'middle': len(b) // 2, 'header': 12}[how]
    b[at] ^= 0x20
open(name, 'wb').write(b)
PY
}
for how in middle header truncate; do
  for src in cornell_none caustic mappings_none; do
    bad="$work/bad_${src}_$how.pbrta"
    damage "$bad" "$work/$src.pbrta" "$how"
    if "$pbrtc" -q --verify "$bad" 2>/dev/null; then
      echo "FAIL: pbrtc --verify accepted $bad" >&2
      exit 1
    fi
    set +e
    out=$(python3 "$reader" --schema "$schema" "$bad" 2>&1)
    status=$?
    set -e
    if [ "$status" -ne 1 ] || ! grep -q "error:" <<<"$out" || grep -q Traceback <<<"$out"; then
      echo "FAIL: the spec reader did not refuse $bad cleanly (exit $status):" >&2
      echo "$out" >&2
      exit 1
    fi
    echo "refused as it should be: $out"
  done
done
echo "PASS"
