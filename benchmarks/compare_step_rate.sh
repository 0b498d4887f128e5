#!/usr/bin/env bash
# Before/after step rate of two poresph builds on one scene, the method of run_step_rate.sh:
# particle-steps per second from the steady part of the progress lines, 1 and 2 threads (THREADS
# overrides), the two builds alternated REPS times, the 1-minute load average printed with each
# run (the machine is shared: keep the quietest readings, compare medians).
# Usage: bash benchmarks/compare_step_rate.sh OLD_PORESPH NEW_PORESPH SCENE [REPS]
set -uo pipefail
OLD=${1:?usage: compare_step_rate.sh OLD_BINARY NEW_BINARY SCENE [REPS]}
NEW=${2:?}
SCENE=${3:?}
REPS=${4:-3}
np=$("$NEW" info "$SCENE" | awk '/^particles:/ { print $2 }')
for rep in $(seq 1 "$REPS"); do
  for t in ${THREADS:-1 2}; do
    for which in old new; do
      bin=$OLD; [ "$which" = new ] && bin=$NEW
      out=$(mktemp -d)
      load0=$(cut -d' ' -f1 /proc/loadavg)
      log=$("$bin" run "$SCENE" --out "$out" --force --threads "$t" 2>&1)
      load1=$(cut -d' ' -f1 /proc/loadavg)
      echo "$log" | awk -v t="$t" -v np="$np" -v w="$which" -v rep="$rep" -v l0="$load0" -v l1="$load1" '
        # wall is printed as "12.3 s", "2 min 5 s" or "1 h 3 min"
        function secs(i,   s) { s = 0
          for (; i <= NF; i += 2) { if ($(i+1) == "s") return s + $i; if ($(i+1) == "min") s += 60 * $i
                                    else if ($(i+1) == "h") s += 3600 * $i; else return s } return s }
        /^step / { s = $2; for (i = 1; i <= NF; ++i) if ($i == "wall") wl = secs(i + 1); if (!n++) { s0 = s; w0 = wl } }
        END { if (n < 2 || wl <= w0) { print "rep " rep " " w " threads " t ": too few progress lines"; exit 0 }
              r = (s - s0) / (wl - w0)
              printf "rep %d %s threads %d: %.4g s/step, %.3g particle-steps/s, load %s -> %s\n", rep, w, t, 1 / r, r * np, l0, l1 }'
      rm -rf "$out"
    done
  done
done
