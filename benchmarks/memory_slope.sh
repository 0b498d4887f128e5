#!/bin/bash
# Bytes per particle as the SLOPE of peak RSS between resolutions of case A (issue 17, memory):
# set-up, libraries and other constants cancel. docs/performance.md "Memory: the RSS slope".
#
# For each neighbour_list mode (NLIST, default "half cells") and each spacing (DX, default
# "0.01 0.0075") it runs benchmarks/scenes/dam_break_caseA_cubic.yaml for STEPS steps (default 5)
# on one thread under /usr/bin/time -v and prints particles, peak RSS and the bytes held by
# `poresph info` (its total line); then the slope between the first and last spacing.
# With DSPH_BIN and DSPH_CASES ("0.01:DIR/Dam 0.0075:DIR/Dam", cases made by GenCase with those
# dp, ../shared/benchmarks/README.md) the same for DualSPHysics (-tmax DSPH_TMAX, 0.001).
#
# Usage: [NLIST=...] [DX=...] [STEPS=5] [DSPH_BIN=... DSPH_CASES=...] bash benchmarks/memory_slope.sh [BUILD_DIR]
set -u
BUILD=${1:-build}
NLIST=${NLIST:-"half cells"}
DX=${DX:-"0.01 0.0075"}
STEPS=${STEPS:-5}
SCENE=${SCENE:-$(dirname "$0")/scenes/dam_break_caseA_cubic.yaml}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
export OMP_NUM_THREADS=1

slope() {  # label, then "N RSSkB" lines on stdin
  awk -v what="$1" 'NR == 1 {n1 = $1; r1 = $2} {n2 = $1; r2 = $2}
    END {if (n2 != n1) printf "%s: slope %.1f B/particle (%d -> %d particles, %.1f -> %.1f MB)\n",
         what, (r2 - r1) * 1024 / (n2 - n1), n1, n2, r1 / 1024, r2 / 1024}'
}

for mode in $NLIST; do
  : > "$TMP/$mode.points"
  for dx in $DX; do
    s="$TMP/caseA_${mode}_$dx.yaml"
    sed -e "s/^spacing: .*/spacing: $dx/" -e "s/^end_time: .*/end_time: 100.0/" \
        -e "s/^max_steps: .*/max_steps: $STEPS/" "$SCENE" > "$s"
    echo "neighbour_list: $mode" >> "$s"
    info=$("$BUILD/poresph" info "$s" --threads 1 --estimate-steps 2 2>&1)
    n=$(echo "$info" | awk '/^particles:/ { print $2 }')
    held=$(echo "$info" | grep -E '^ +total ' | awk '{print $2}')
    /usr/bin/time -v "$BUILD/poresph" run "$s" --out "$TMP/run_${mode}_$dx" --threads 1 \
      > "$TMP/run.log" 2> "$TMP/time.log" &
    # Resident memory while stepping: VmRSS sampled every 0.1 s from the first progress line
    # (after step 1: the initial snapshot is written before it) until a line reports step
    # STEPS - 1 (the final snapshot and checkpoint come after the last step). Progress lines
    # come at most once a wall second (stderr): with steps shorter than that the window is
    # only approximate.
    step_rss=0
    while kill -0 $! 2> /dev/null; do
      pid=$(pgrep -P $! -x poresph | head -1)
      k=$(awk '/^step / { k = $2 } END { print k + 0 }' "$TMP/time.log" 2> /dev/null)
      if [ -n "$pid" ] && [ "${k:-0}" -ge 1 ] && [ "${k:-0}" -lt $((STEPS - 1)) ]; then
        v=$(awk '/^VmRSS/ {print $2}' /proc/"$pid"/status 2> /dev/null)
        [ -n "$v" ] && [ "$v" -gt "$step_rss" ] && step_rss=$v
      fi
      sleep 0.1
    done
    wait $!
    rss=$(grep 'Maximum resident' "$TMP/time.log" | awk '{print $NF}')
    cpu=$(awk -F': ' '/User time/ {u = $2} /System time/ {s = $2} END {print u + s}' "$TMP/time.log")
    echo "PoreSPH $mode dx $dx: $n particles, peak RSS $rss kB, RSS while stepping $step_rss kB," \
         "held (info) $held B/particle, CPU ${cpu} s, load $(cut -d' ' -f1 /proc/loadavg)"
    echo "$n $rss" >> "$TMP/$mode.points"
    echo "$n $step_rss" >> "$TMP/$mode.stepping"
  done
  slope "PoreSPH $mode, peak RSS" < "$TMP/$mode.points"
  slope "PoreSPH $mode, RSS while stepping" < "$TMP/$mode.stepping"
done

if [ -n "${DSPH_BIN:-}" ] && [ -n "${DSPH_CASES:-}" ]; then
  : > "$TMP/dsph.points"
  for c in $DSPH_CASES; do
    dx=${c%%:*}; case_=${c#*:}
    /usr/bin/time -v "$DSPH_BIN" -cpu -ompthreads:1 "$case_" "$TMP/dsph_$dx" -tmax:"${DSPH_TMAX:-0.001}" \
      -tout:10 -sv:none -svtimers:1 > "$TMP/dsph.log" 2> "$TMP/time.log"
    rss=$(grep 'Maximum resident' "$TMP/time.log" | awk '{print $NF}')
    n=$(grep -o 'Total particles: [0-9,]*' "$TMP/dsph_$dx/Run.out" | head -1 | tr -dc '0-9')
    echo "DualSPHysics dp $dx: $n particles, peak RSS $rss kB, load $(cut -d' ' -f1 /proc/loadavg)"
    echo "$n $rss" >> "$TMP/dsph.points"
  done
  slope "DualSPHysics" < "$TMP/dsph.points"
fi
