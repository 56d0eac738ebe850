#!/usr/bin/env bash
# Renders reference scenes of ../shared/refs (and the project's own scenes in
# tests/convergence/own, whose references pbrt-v3 rendered at high spp) and
# checks that each converges to pbrt-v3's image (the rule is in tools/compare/convergence.h): pbrtc compiles
# the scene, pbrtrun renders it twice at half the reference's spp with seeds 1
# and 2 at the reference's --resdiv, and ref-compare judges the pair and
# writes ours | pbrt-v3 | signed difference as a PNG for people to look at.
#
#   tools/convergence.sh [--build DIR] [--out DIR] [--ci] [NAME-FILTER]
#
# --ci runs only the scenes marked "ci" in tests/convergence/scenes.txt.
# Exit status: 0 when every scene run converges; 1 otherwise.
set -uo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build"
out="$root/build/convergence"
only_ci=0
filter=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --ci) only_ci=1; shift ;;
    -h|--help) sed -n 2,13p "$0"; exit 0 ;;
    *) filter="$1"; shift ;;
  esac
done
shared="${PBRTC_SHARED_DIR:-$root/../shared}"
if [ ! -d "$shared/scenes" ] || [ ! -d "$shared/refs" ]; then
  echo "convergence: error: shared corpus not found at $shared (set PBRTC_SHARED_DIR)" >&2
  exit 2
fi
for tool in pbrtc pbrtrun ref-compare; do
  if [ ! -x "$build/$tool" ]; then
    echo "convergence: error: $build/$tool is not built" >&2
    exit 2
  fi
done
mkdir -p "$out"

status=0
ran=0
printf '%-62s %s\n' "scene" "result"
while read -r entry ref spp resdiv ci ours extra; do
  case "$entry" in ''|'#'*) continue ;; esac
  [ "$only_ci" = 1 ] && [ "$ci" != "ci" ] && continue
  [ -n "$filter" ] && [[ "$entry" != *"$filter"* ]] && continue
  # own/...: the project's scenes, reference beside the scene; else the shared corpus.
  case "$entry" in
    own/*) scene="$root/tests/convergence/$entry"; refpath="$(dirname "$scene")/$ref" ;;
    *) scene="$shared/scenes/$entry"; refpath="$shared/refs/$ref" ;;
  esac
  # A 6th column "v3-no-hdr" (shared scenes): compile the scene as pbrt-v3 sees it
  # (tools/compile_as_v3.sh).
  as_v3=0
  if [ "$ours" = "v3-no-hdr" ]; then as_v3=1; ours=""; fi
  # "renders=N" after our spp (mlt, sppm: noise correlated between pixels): N renders of
  # ours / N spp each, seeds 1..N, judged by the spread of their block means (ref-compare
  # --spread). Otherwise two renders of ours / 2.
  renders=2
  case "$extra" in renders=*) renders="${extra#renders=}" ;; esac
  ours="${ours:-$spp}"
  name="$(basename "${ref%.exr}")"
  archive="$out/$name.pbrta"
  half=$((ours / renders))
  log="$out/$name.log"
  ran=$((ran + 1))
  if [ "$as_v3" = 1 ]; then
    compile() { "$root/tools/compile_as_v3.sh" "$build/pbrtc" "$scene" "$archive"; }
  else
    compile() { "$build/pbrtc" -q "$scene" -o "$archive"; }
  fi
  if ! compile >"$log" 2>&1; then
    printf '%-62s %s\n' "$entry" "COMPILE FAILED: $(grep -m1 error "$log")"
    status=1
    continue
  fi
  ok=1
  for ((seed = 1; seed <= renders; ++seed)); do
    # Each render has half the samples; textures are filtered as for the
    # reference's count (pbrt-v3 scales differentials by 1/sqrt(spp)).
    if ! "$build/pbrtrun" --quiet "$archive" --spp "$half" --resdiv "$resdiv" --seed "$seed" \
        --differential-spp "$spp" \
        --outfile "$out/$name.$seed.exr" >>"$log" 2>&1; then
      ok=0
      break
    fi
  done
  if [ "$ok" = 0 ]; then
    printf '%-62s %s\n' "$entry" "NOT RENDERED: $(tail -n1 "$log")"
    status=1
    continue
  fi
  files=()
  for ((seed = 1; seed <= renders; ++seed)); do files+=("$out/$name.$seed.exr"); done
  spread=()
  [ "$renders" -gt 2 ] && spread=(--spread)
  result="$("$build/ref-compare" "${spread[@]}" "${files[@]}" "$refpath" \
      --spp "$ours" --reference-spp "$spp" --png "$out/$name.png" 2>&1)"
  rc=$?
  printf '%-62s %s\n' "$entry" "${result#*: }"
  [ $rc -ne 0 ] && status=1
done < "$root/tests/convergence/scenes.txt"
if [ "$ran" = 0 ]; then
  echo "convergence: error: no scene matched" >&2
  exit 2
fi
exit $status
