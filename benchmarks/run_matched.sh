#!/usr/bin/env bash
# The matched cases of issue 17, PoreSPH and (optionally) DualSPHysics side by side:
#   A  benchmarks/scenes/dam_break_caseA_cubic.yaml  (DSPH 01_DamBreak at dp 0.01: cubic, h/dx 1.732)
#   B  benchmarks/scenes/dam_break_3d.yaml           (Wendland, h/dx 1.3; DSPH coefh 0.7506 -wendland)
# For each repetition, thread count and case the programs run one after the other (alternated),
# and each run prints: s/step (steady part of the progress lines; DSPH: Simulation Runtime /
# steps), particle-steps/s for all particles and for the fluid ones only, the physical time
# simulated per wall second, the CPU time per step (user + sys of the whole run / steps: set-up
# included, the figure to compare on a loaded machine with 1 thread) and the load average.
#
# Usage: bash benchmarks/run_matched.sh [BUILD_DIR]
# Environment:
#   STEPS=40        PoreSPH steps per run (max_steps of a temporary copy of the scene)
#   THREADS="1 2"   thread counts;  REPS=1  repetitions;  CASES="A B"
#   DSPH_BIN=path/DualSPHysics5.4CPU_linux64     run DualSPHysics too (see ../shared/benchmarks/README.md)
#   DSPH_A=path/out_dp0.01/Dam  DSPH_B=path/out_B/Dam   its GenCase outputs of case A and B
#   DSPH_TMAX=0.004  physical time of a DSPH run (~1e-4 s per step: 0.004 s ~ 40 steps)
#   SKIN=0.3        neighbour_skin (units of dx) written into the PoreSPH scenes (default: the scene's)
#   NLIST="full half"  neighbour_list values run one after the other (default: the scene's, auto)
#   PREC="double float"  fluid pair_precision values run one after the other (half list only;
#                    default: the scene's, double); labels poresph-<list>-<precision>
#   SHORT=1          also run each program for ~5 steps (PoreSPH max_steps 5, DSPH tmax 0.0005)
#                    and print the CPU time per step of the difference (set-up and output cancel:
#                    the figure to compare on a loaded machine, with THREADS=1)
set -uo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
PORESPH=$BUILD_DIR/poresph
STEPS=${STEPS:-40}
THREADS=${THREADS:-1 2}
REPS=${REPS:-1}
CASES=${CASES:-A B}
DSPH_TMAX=${DSPH_TMAX:-0.004}
scene_of() { case $1 in A) echo benchmarks/scenes/dam_break_caseA_cubic.yaml ;;
                         B) echo benchmarks/scenes/dam_break_3d.yaml ;; esac; }
dsph_case_of() { case $1 in A) echo "${DSPH_A:-}" ;; B) echo "${DSPH_B:-}" ;; esac; }

cpu_of() {  # command...: prints user + sys seconds
  local f
  f=$(mktemp)
  /usr/bin/time -f "%U %S" -o "$f" "$@" > /dev/null 2>&1
  awk '{ print $1 + $2 }' "$f"
  rm -f "$f"
}

run_poresph() {  # case threads rep [neighbour_list] [pair_precision]
  local scene tmp out log np nf load0 load1 cpu label=poresph
  scene=$(scene_of "$1")
  tmp=$(mktemp -d)
  sed -e "s/^max_steps:.*/max_steps: $STEPS/" -e "s/^end_time:.*/end_time: 10.0/" "$scene" > "$tmp/scene.yaml"
  if [ -n "${SKIN:-}" ]; then
    sed -i -e '/^neighbour_skin:/d' -e "s/^kernel:.*/&\nneighbour_skin: $SKIN/" "$tmp/scene.yaml"
  fi
  if [ -n "${4:-}" ]; then
    sed -i -e '/^neighbour_list:/d' -e "s/^kernel:.*/&\nneighbour_list: $4/" "$tmp/scene.yaml"
    label="poresph-$4"
  fi
  if [ -n "${5:-}" ]; then
    sed -i -e '/^  pair_precision:/d' -e "s/^fluid:.*/&\n  pair_precision: $5/" "$tmp/scene.yaml"
    label="$label-$5"
  fi
  local c5 cN
  if [ -n "${SHORT:-}" ]; then
    sed -e "s/^max_steps:.*/max_steps: 5/" "$tmp/scene.yaml" > "$tmp/short.yaml"
    c5=$(cpu_of "$PORESPH" run "$tmp/short.yaml" --out "$tmp/o5" --force --threads "$2")
  fi
  grep -q '^max_steps:' "$tmp/scene.yaml" || echo "max_steps: $STEPS" >> "$tmp/scene.yaml"
  np=$("$PORESPH" info "$tmp/scene.yaml" | awk '/^particles:/ { print $2 }')
  nf=$("$PORESPH" info "$tmp/scene.yaml" | awk '/\(model fluid\)/ { s += $2 } END { print s + 0 }')
  load0=$(cut -d' ' -f1 /proc/loadavg)
  log=$( { /usr/bin/time -f "CPUTIME %U %S" "$PORESPH" run "$tmp/scene.yaml" --out "$tmp/out" --force \
           --threads "$2" ; } 2>&1)
  load1=$(cut -d' ' -f1 /proc/loadavg)
  echo "$log" | awk -v lb="$label" -v c="$1" -v t="$2" -v np="$np" -v nf="$nf" -v rep="$3" -v l0="$load0" -v l1="$load1" '
    # wall is printed as "12.3 s", "2 min 5 s" or "1 h 3 min"
    function secs(i,   s) { s = 0
      for (; i <= NF; i += 2) { if ($(i+1) == "s") return s + $i; if ($(i+1) == "min") s += 60 * $i
                                else if ($(i+1) == "h") s += 3600 * $i; else return s } return s }
    /^step / { s = $2; tt = $5; for (i = 1; i <= NF; ++i) if ($i == "wall") w = secs(i + 1)
               if (!n++) { s0 = s; w0 = w; t0 = tt } }
    /^CPUTIME/ { cpu = $2 + $3 }
    END { if (n < 2 || w <= w0) { print "case " c " poresph threads " t ": too few progress lines"; exit 0 }
          r = (s - s0) / (w - w0)
          printf "rep %d case %s %s threads %d: %.4f s/step, %.3g particle-steps/s (%d particles), %.3g fluid particle-steps/s (%d), %.3g s simulated per wall s, CPU %.4f s/step (whole run / %d steps), load %s -> %s\n",
                 rep, c, lb, t, 1 / r, r * np, np, r * nf, nf, (tt - t0) / (w - w0), cpu / s, s, l0, l1 }'
  if [ -n "${SHORT:-}" ]; then
    cN=$(echo "$log" | awk '/^CPUTIME/ { print $2 + $3 }')
    awk -v lb="$label" -v a="$c5" -v b="$cN" -v n="$STEPS" -v c="$1" -v t="$2" -v rep="$3" -v l="$(cut -d' ' -f1 /proc/loadavg)" 'BEGIN {
      printf "rep %d case %s %s threads %d: CPU %.4f s/step (difference of %d- and 5-step runs), load %s\n", rep, c, lb, t, (b - a) / (n - 5), n, l }'
  fi
  rm -rf "$tmp"
}

run_dsph() {  # case threads rep
  local dcase out load0 load1 cpu log
  dcase=$(dsph_case_of "$1")
  [ -n "${DSPH_BIN:-}" ] && [ -n "$dcase" ] || return 0
  out=$(mktemp -d)
  local extra=""
  [ "$1" = B ] && extra="-wendland"
  load0=$(cut -d' ' -f1 /proc/loadavg)
  log=$( { /usr/bin/time -f "CPUTIME %U %S" "$DSPH_BIN" -cpu -ompthreads:"$2" $extra "$dcase" "$out" \
           -tmax:"$DSPH_TMAX" -tout:"$DSPH_TMAX" -sv:none -svtimers:1 ; } 2>&1)
  load1=$(cut -d' ' -f1 /proc/loadavg)
  if [ -n "${SHORT:-}" ]; then
    local c5 o5
    o5=$(mktemp -d)
    c5=$(cpu_of "$DSPH_BIN" -cpu -ompthreads:"$2" $extra "$dcase" "$o5" -tmax:0.0005 -tout:0.0005 -sv:none)
    local s5
    s5=$(awk '/^Steps of simulation/ { split($0, a, ":"); print a[2] + 0 }' "$o5/Run.out")
    rm -rf "$o5"
  fi
  { echo "$log" | grep CPUTIME; cat "$out/Run.out"; } | awk -v c="$1" -v t="$2" -v rep="$3" -v l0="$load0" -v l1="$load1" -v tm="$DSPH_TMAX" '
    /^CPUTIME/ { cpu = $2 + $3 }
    /Simulation Runtime/ { for (i = 1; i <= NF; ++i) if ($i + 0 > 0) { rt = $i + 0; break } }
    /^Particles of simulation \(initial\)/ { split($0, a, ":"); gsub(",", "", a[2]); np = a[2] + 0 }
    /^Total particles:.*fluid=/ { f = $0; sub(/.*fluid=/, "", f); nf = f + 0 }
    /^Steps of simulation/ { split($0, a, ":"); steps = a[2] + 0 }
    END { if (!(steps > 0) || !(rt > 0)) { print "case " c " dsph threads " t ": no Run.out figures"; exit 0 }
          r = steps / rt
          printf "rep %d case %s dsph    threads %d: %.4f s/step, %.3g particle-steps/s (%d particles), %.3g fluid particle-steps/s (%d), %.3g s simulated per wall s, CPU %.4f s/step (whole run / %d steps), load %s -> %s\n",
                 rep, c, t, 1 / r, r * np, np, r * nf, nf, tm / rt, cpu / steps, steps, l0, l1
          if (c5 != "") printf "rep %d case %s dsph    threads %d: CPU %.4f s/step (difference of %d- and %d-step runs), load %s\n", rep, c, t, (cpu - c5) / (steps - s5), steps, s5, l1 }' c5="${c5:-}" s5="${s5:-0}"
  rm -rf "$out"
}

for rep in $(seq 1 "$REPS"); do
  for t in $THREADS; do
    for c in $CASES; do
      if [ -n "${PREC:-}" ]; then
        for pr in $PREC; do run_poresph "$c" "$t" "$rep" "${NLIST:-half}" "$pr"; done
      elif [ -n "${NLIST:-}" ]; then
        for nl in $NLIST; do run_poresph "$c" "$t" "$rep" "$nl"; done
      else
        run_poresph "$c" "$t" "$rep"
      fi
      run_dsph "$c" "$t" "$rep"
    done
  done
done
