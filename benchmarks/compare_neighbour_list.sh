#!/usr/bin/env bash
# Full against half neighbour list (scene key neighbour_list, docs/performance.md "Half
# neighbour list") on one scene: the two alternated run by run, REPS times, for each thread
# count. Per run: s/step from the steady part of the progress lines (run_step_rate.sh method),
# user CPU seconds per step of the whole run, peak RSS (/usr/bin/time -v) and the 1-minute load
# average before and after. Then `poresph info` of each (bytes per particle held after a timed
# step). The scene is copied with max_steps, neighbour_skin and neighbour_list replaced.
# Usage: [REPS=3] [THREADS="1 2"] [STEPS=30] [SKIN=0.3] bash benchmarks/compare_neighbour_list.sh SCENE [BUILD_DIR]
set -uo pipefail
SCENE=${1:?usage: compare_neighbour_list.sh SCENE [BUILD_DIR]}
BUILD_DIR=${2:-build}
BIN="$BUILD_DIR/poresph"
REPS=${REPS:-3}
STEPS=${STEPS:-30}
SKIN=${SKIN:-0.3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for mode in full half; do
  sed -e '/^max_steps:/d' -e '/^neighbour_skin:/d' -e '/^neighbour_list:/d' "$SCENE" > "$tmp/$mode.yaml"
  printf '\nmax_steps: %s\nneighbour_skin: %s\nneighbour_list: %s\n' "$STEPS" "$SKIN" "$mode" >> "$tmp/$mode.yaml"
done
np=$("$BIN" info "$tmp/full.yaml" | awk '/^particles:/ { print $2 }')
echo "scene $SCENE: $np particles, $STEPS steps, skin $SKIN dx, $(date -u '+%Y-%m-%d %H:%M UTC')"
for rep in $(seq 1 "$REPS"); do
  for t in ${THREADS:-1 2}; do
    for mode in full half; do
      out="$tmp/out_$mode"
      load0=$(cut -d' ' -f1 /proc/loadavg)
      log=$(OMP_NUM_THREADS=$t /usr/bin/time -v "$BIN" run "$tmp/$mode.yaml" --out "$out" --force --threads "$t" 2>&1)
      load1=$(cut -d' ' -f1 /proc/loadavg)
      echo "$log" | awk -v t="$t" -v np="$np" -v m="$mode" -v rep="$rep" -v l0="$load0" -v l1="$load1" -v steps="$STEPS" '
        function secs(i,   s) { s = 0
          for (; i <= NF; i += 2) { if ($(i+1) == "s") return s + $i; if ($(i+1) == "min") s += 60 * $i
                                    else if ($(i+1) == "h") s += 3600 * $i; else return s } return s }
        /^step / { s = $2; for (i = 1; i <= NF; ++i) if ($i == "wall") wl = secs(i + 1); if (!n++) { s0 = s; w0 = wl } }
        /User time \(seconds\)/ { user = $NF }
        /Maximum resident set size/ { rss = $NF }
        END { r = (n >= 2 && wl > w0) ? (s - s0) / (wl - w0) : 0
              printf "rep %d %-4s threads %d: %s s/step (steady), user CPU %.3f s/step (whole run), peak RSS %.0f MB = %.0f B/particle, load %s -> %s\n",
                     rep, m, t, (r > 0 ? sprintf("%.4f", 1 / r) : "n/a"), user / steps, rss / 1024, rss * 1024 / np, l0, l1 }'
    done
  done
done
for mode in full half; do
  echo "== poresph info ($mode, 1 thread, after 2 timed steps)"
  OMP_NUM_THREADS=1 "$BIN" info "$tmp/$mode.yaml" --threads 1 --estimate-steps 2 |
    awk '/^estimate:/ || /^neighbours:/ { print } /^memory by owner/ { on = 1 } on { print } /^  total/ { on = 0 }'
done
