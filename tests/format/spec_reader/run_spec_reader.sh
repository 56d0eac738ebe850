#!/usr/bin/env bash
# Compiles real shared scenes with the built pbrtc, in each codec, and reads every archive with
# read_pbrta.py: a reader written from format/ARCHIVE.md and SCHEMA.md alone, which must check
# each archive as the spec says and print the same summary as `pbrtc --info`. Then damaged
# copies must be refused. A format change that the spec does not describe fails here.
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
compile anim "$s/rs-anim-bluespheres/anim-bluespheres.pbrt"
compile instances "$s/hm-instances/pbrt-v3-rs/scenes/objects/instances.pbrt"

# Its 4 MB of texels are one section stored as codec 5 (checksummed by 1 MiB chunks).
if ! "$pbrtc" --info "$work/mappings_none.pbrta" | grep -q "texels *none_chunked"; then
  echo "FAIL: mappings_none.pbrta has no codec-5 texels section to read" >&2
  exit 1
fi
# Its 2 MiB of geometry cost under 1% more in 1 MiB frames: codec 6.
if ! "$pbrtc" --info "$work/caustic.pbrta" | grep -q "geometry *zstd_shuffle4_frames_1m"; then
  echo "FAIL: caustic.pbrta has no codec-6 geometry section to read" >&2
  exit 1
fi
python3 "$reader" --schema "$schema" --pbrtc "$pbrtc" "$work"/*.pbrta

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
