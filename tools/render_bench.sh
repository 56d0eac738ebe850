#!/usr/bin/env bash
# pbrtrun against pbrt-v3, side by side: both programs render the same reference scenes at the
# same settings (the reference's spp and --resdiv, or --spp N), on this machine, in the same
# minutes, interleaved (pbrt-v3, pbrtrun, pbrt-v3, ... for --rounds rounds), with 1 and 2
# threads. Never divides by a figure recorded elsewhere. A benchmark: never run in CI (but for a
# one-sample smoke test).
#
#   tools/render_bench.sh [--build DIR] [--threads "1 2"] [--rounds N] [--spp N] [--skip TEXT]...
#                         [--each] [NAME-FILTER]
#
# Entries whose name contains NAME-FILTER are measured (all without one), less those containing
# any --skip TEXT (v3-figures/f10-1ac takes 512 light samples per camera sample, so a survey of
# every scene at one --spp usually skips it: --skip f10-1ac).
#
# pbrt-v3 is ../shared/peers/pbrt-v3/pbrt (its README). Prints the CPU, then a Markdown table per
# scene and thread count: each program's whole-process time (best and worst of the rounds), its
# render-only time, and the ratios of pbrt-v3's to pbrtrun's (their range over the rounds, paired
# round by round; --each also prints every round's pair to stderr). Whole process: pbrt-v3 parses the scene text, pbrtrun loads the archive
# pbrtc compiled beforehand (compiling is not timed). Render only: pbrtrun's own --stats figure;
# pbrt-v3 prints none, so its whole time less its load time, measured as its best whole time at
# --spp 1 and a tiny resolution with the same thread count (which still parses and builds
# everything); n/a for mlt, whose bootstrap that tiny run still does in full (compare mlt's
# whole times). Then peak RSS.
# Scenes marked v3-no-hdr in scenes.txt are compiled as pbrt-v3 sees them (its .hdr maps are a
# constant there: tools/compile_as_v3.sh), so both programs do the same work; the table says so.
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build"
threads="1 2"
rounds=3
each=0
spp_override=""
filter=""
skips=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --rounds) rounds="$2"; shift 2 ;;
    --spp) spp_override="$2"; shift 2 ;;
    --skip) skips+=("$2"); shift 2 ;;
    --each) each=1; shift ;;
    -h|--help) sed -n 2,25p "$0"; exit 0 ;;
    *) filter="$1"; shift ;;
  esac
done
shared="${PBRTC_SHARED_DIR:-$root/../shared}"
v3="$shared/peers/pbrt-v3/pbrt"
for program in "$v3" "$build/pbrtc" "$build/pbrtrun"; do
  if [ ! -x "$program" ]; then
    echo "render_bench: $program not found (build first; pbrt-v3: ../shared/peers)" >&2
    exit 1
  fi
done
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

# Runs a command, prints "wall_seconds peak_rss_kib" (GNU time's format, from bash's own clock
# when /usr/bin/time is missing); its output goes to $out/last.log.
timed() {
  if [ -x /usr/bin/time ]; then
    /usr/bin/time -f "%e %M" -o "$out/time" "$@" >"$out/last.log" 2>&1 || return 1
    cat "$out/time"
  else
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >"$out/last.log" 2>&1 || return 1
    t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f 0\n", b - a }'
  fi
}
# min and max of whitespace-separated numbers.
range() { tr ' ' '\n' | awk 'NF { v = $1 + 0; if (n++ == 0 || v < lo) lo = v; if (n == 1 || v > hi) hi = v }
  END { if (n) printf "%.2f-%.2f", lo, hi }'; }

cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
isa="$(grep -m1 -o -w -e avx512f /proc/cpuinfo || grep -m1 -o -w -e avx2 /proc/cpuinfo || echo sse)"
echo "CPU: $cpu ($(nproc) cores, ${isa^^}); $rounds interleaved rounds; $(date -u '+%Y-%m-%d %H:%M UTC')"
echo
echo "| scene | spp | thr | pbrt-v3 s | pbrtrun s | whole v3/run | v3 render s | run render s | render v3/run | RSS v3/run MiB |"
echo "|---|---|---|---|---|---|---|---|---|---|"
while read -r entry ref spp resdiv ci ours _; do
  case "$entry" in ''|'#'*) continue ;; esac
  [ -n "$filter" ] && [[ "$entry" != *"$filter"* ]] && continue
  skipped=false
  for skip in "${skips[@]}"; do [[ "$entry" == *"$skip"* ]] && skipped=true; done
  $skipped && continue
  [ -n "$spp_override" ] && spp="$spp_override"
  # own/...: the project's scenes (tests/convergence/own), else the shared corpus.
  case "$entry" in
    own/*) scene="$root/tests/convergence/$entry" ;;
    *) scene="$shared/scenes/$entry" ;;
  esac
  # "v3-no-hdr": the scene as pbrt-v3 sees it (its .hdr maps are constant there), so that both
  # programs do the same work; the table marks such scenes.
  compile=("$build/pbrtc" -q "$scene" -o "$out/s.pbrta")
  if [ "$ours" = "v3-no-hdr" ]; then
    compile=("$root/tools/compile_as_v3.sh" "$build/pbrtc" "$scene" "$out/s.pbrta")
    entry="$entry (no .hdr, as pbrt-v3)"
  fi
  if ! "${compile[@]}" 2>"$out/compile.log"; then
    echo "| $entry | $spp | - | compile failed: $(tail -n1 "$out/compile.log") | | | | | | |"
    continue
  fi
  # mlt: pbrt-v3's tiny load run below would still do its whole bootstrap (its paths do not
  # depend on the resolution), leaving no render time to compare: only the whole-process ratio
  # means anything there, so that run is skipped.
  mlt=0
  grep -Eq '^[[:space:]]*Integrator[[:space:]]+"mlt"' "$scene" && mlt=1
  for t in $threads; do
    # pbrt-v3's load (parse, build, one tiny pass), best of the rounds, at this thread count:
    # part of it runs in parallel (the realistic camera's exit pupil bounds, seconds of work).
    v3_load=""
    for ((r = 0; r < rounds && mlt == 0; ++r)); do
      s=$(timed "$v3" --quiet --nthreads "$t" --spp 1 --resdiv 64 --outfile "$out/tiny.exr" \
          "$scene") || break
      v3_load="$v3_load ${s%% *}"
    done
    v3_load="$(tr ' ' '\n' <<<"$v3_load" | awk 'NF { if (!n++ || $1 < m) m = $1 } END { print m + 0 }')"
    v3_whole="" run_whole="" v3_render="" run_render="" whole_ratio="" render_ratio=""
    v3_rss=0 run_rss=0 failed=""
    for ((r = 0; r < rounds; ++r)); do
      a=$(timed "$v3" --quiet --nthreads "$t" --spp "$spp" --resdiv "$resdiv" \
          --outfile "$out/v3.exr" "$scene") || { failed="pbrt-v3: $(tail -n1 "$out/last.log")"; break; }
      b=$(timed "$build/pbrtrun" --quiet --stats --nthreads "$t" --spp "$spp" --resdiv "$resdiv" \
          "$out/s.pbrta" --outfile "$out/run.exr") || { failed="pbrtrun: $(tail -n1 "$out/last.log")"; break; }
      rr="$(sed -n 's/^ *render  *\([0-9.]*\) s.*/\1/p' "$out/last.log" | head -n1)"
      aw=${a%% *} bw=${b%% *}
      vr="$(awk -v w="$aw" -v l="$v3_load" 'BEGIN { x = w - l; printf "%.3f", (x > 0 ? x : 0) }')"
      v3_whole="$v3_whole $aw" run_whole="$run_whole $bw"
      v3_render="$v3_render $vr" run_render="$run_render ${rr:-0}"
      whole_ratio="$whole_ratio $(awk -v a="$aw" -v b="$bw" 'BEGIN { if (b > 0) print a / b }')"
      render_ratio="$render_ratio $(awk -v a="$vr" -v b="${rr:-0}" 'BEGIN { if (b > 0) print a / b }')"
      if [ "$each" = 1 ]; then
        echo "  round $((r + 1)) $entry ${t}t: pbrt-v3 ${aw} s (render $vr), pbrtrun ${bw} s" \
          "(render ${rr:-0}), render v3/run ${render_ratio##* }" >&2
      fi
      v3_rss=$(( ${a##* } > v3_rss ? ${a##* } : v3_rss ))
      run_rss=$(( ${b##* } > run_rss ? ${b##* } : run_rss ))
    done
    if [ -n "$failed" ]; then
      echo "| $entry | $spp | $t | $failed | | | | | | |"
      continue
    fi
    v3_render_cell="$(range <<<"$v3_render")" render_cell="$(range <<<"$render_ratio")x"
    if [ "$mlt" = 1 ]; then v3_render_cell="-" render_cell="n/a (mlt: see whole)"; fi
    echo "| $entry | $spp | $t | $(range <<<"$v3_whole") | $(range <<<"$run_whole") |" \
      "$(range <<<"$whole_ratio")x | $v3_render_cell | $(range <<<"$run_render") |" \
      "$render_cell | $((v3_rss / 1024))/$((run_rss / 1024)) |"
  done
done < "$root/tests/convergence/scenes.txt"
echo
echo "pbrt-v3's render time is its whole time less its load (measured per scene and thread count"
echo "at --spp 1 --resdiv 64); ratios are paired round by round, over $rounds rounds."
