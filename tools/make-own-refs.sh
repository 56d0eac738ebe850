#!/usr/bin/env bash
# Renders the references of the project's own convergence scenes
# (tests/convergence/own/*.pbrt) with pbrt-v3 itself, the measuring instrument
# in ../shared/peers/pbrt-v3 (never with pbrtrun): each at the spp that
# tests/convergence/scenes.txt lists for it, with the 02sequence sampler's
# default seed. Run it after changing one of those scenes, and commit the EXRs.
#
#   tools/make-own-refs.sh [NAME-FILTER]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
shared="${PBRTC_SHARED_DIR:-$root/../shared}"
pbrt="$shared/peers/pbrt-v3/pbrt"
[ -x "$pbrt" ] || { echo "make-own-refs: error: $pbrt not found" >&2; exit 2; }
filter="${1:-}"
while read -r entry ref spp resdiv ci ours extra; do
  case "$entry" in own/*) ;; *) continue ;; esac
  # A reference named after another scene is borrowed (mlt-lights is judged against
  # bdpt-lights' image of the same world): that scene's entry renders it.
  [ "$(basename "${ref%.exr}")" = "$(basename "${entry%.pbrt}")" ] || continue
  [ -n "$filter" ] && [[ "$entry" != *"$filter"* ]] && continue
  dir="$root/tests/convergence/$(dirname "$entry")"
  echo "make-own-refs: $entry at $spp spp"
  (cd "$dir" && "$pbrt" --quiet --spp "$spp" --resdiv "$resdiv" --outfile "$dir/$ref" \
    "$(basename "$entry")")
done < "$root/tests/convergence/scenes.txt"
