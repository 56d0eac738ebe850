#!/usr/bin/env bash
# Samples per second and time to first pixels of pbrtrun on the shared
# reference scenes at the reference settings (full spp, the reference's
# --resdiv), with 1 and 2 threads, beside pbrt-v3's own figures from
# ../shared/refs/README.md (2 threads). A benchmark: never run in CI.
#
#   tools/render_bench.sh [--build DIR] [--threads "1 2"] [NAME-FILTER]
#
# Prints a Markdown table: scene, spp, threads, samples/s, pbrt-v3's
# samples/s (2 threads), the ratio, time to first pixels from the archive.
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build"
threads="1 2"
filter=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    -h|--help) sed -n 2,10p "$0"; exit 0 ;;
    *) filter="$1"; shift ;;
  esac
done
shared="${PBRTC_SHARED_DIR:-$root/../shared}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
echo "| scene | spp | threads | samples/s | pbrt-v3 samples/s (2 thr) | ratio | first pixels s |"
echo "|---|---|---|---|---|---|---|"
while read -r entry ref spp resdiv ci; do
  case "$entry" in ''|'#'*) continue ;; esac
  [ -n "$filter" ] && [[ "$entry" != *"$filter"* ]] && continue
  pbrt_rate="$(awk -F'|' -v e="$entry" '$2 ~ e {gsub(/ /,"",$9); print $9; exit}' "$shared/refs/README.md")"
  if ! "$build/pbrtc" -q "$shared/scenes/$entry" -o "$out/s.pbrta" 2>/dev/null; then
    echo "| $entry | $spp | - | compile failed | $pbrt_rate | | |"
    continue
  fi
  for t in $threads; do
    stats="$("$build/pbrtrun" --quiet --stats --spp "$spp" --resdiv "$resdiv" --nthreads "$t" \
        "$out/s.pbrta" --outfile "$out/img.exr" 2>&1)"
    rate="$(sed -n 's/.*render .*(\([0-9.e+]*\) samples\/s).*/\1/p' <<<"$stats")"
    first="$(sed -n 's/.*time to first pixels *\([0-9.]*\) s.*/\1/p' <<<"$stats")"
    if [ -z "$rate" ]; then
      echo "| $entry | $spp | $t | $(tail -n1 <<<"$stats") | $pbrt_rate | | |"
      continue
    fi
    ratio="$(awk -v a="$rate" -v b="$pbrt_rate" 'BEGIN { if (b > 0) printf "%.2fx", a / b }')"
    echo "| $entry | $spp | $t | $rate | $pbrt_rate | $ratio | $first |"
  done
done < "$root/tests/convergence/scenes.txt"
