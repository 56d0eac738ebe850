#!/usr/bin/env bash
# Runs a libFuzzer binary for a bounded time on a corpus seeded from the
# shared scenes. Usage: run_fuzzer.sh BINARY SECONDS SEED_GLOB...
# The seeds are copied to a scratch directory (the shared corpus is read-only
# and libFuzzer writes new inputs into its first corpus directory).
set -euo pipefail
bin=$(realpath "$1"); seconds=$2; shift 2
if [ ! -x "$bin" ]; then
  echo "FAIL: fuzz binary $bin not built (tools/run-tests.sh builds the build-fuzz tree)" >&2
  exit 1
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/corpus" "$work/seeds"
n=0
for pattern in "$@"; do
  for f in $pattern; do
    [ -f "$f" ] || continue
    # Only the first 64 KiB: the fuzzer's max_len.
    head -c 65536 "$f" > "$work/seeds/seed$n"
    n=$((n + 1))
  done
done
echo "seeded with $n files"
[ "$n" -gt 0 ] || { echo "FAIL: no seed files matched" >&2; exit 1; }
cd "$work"
"$bin" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=4096 -timeout=20 \
  -print_final_stats=1 corpus seeds
