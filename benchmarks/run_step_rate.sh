#!/usr/bin/env bash
# Full-step speed of `poresph run` on one scene, 1 and 2 threads: particle-steps per second (all
# particles, walls included, as DualSPHysics counts them) from the steady part of the progress
# lines: (last step - first step) / (last wall - first wall). Output goes to a temporary folder.
# Usage: bash benchmarks/run_step_rate.sh SCENE [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${1:?usage: run_step_rate.sh SCENE [BUILD_DIR]}
BUILD_DIR=${2:-build}
np=$("$BUILD_DIR/poresph" info "$SCENE" | awk '/^particles:/ { print $2 }')
for t in 1 2; do
  out=$(mktemp -d)
  log=$("$BUILD_DIR/poresph" run "$SCENE" --out "$out" --force --threads "$t" 2>&1)
  echo "$log" | awk -v t="$t" -v np="$np" '
    # wall is printed as "12.3 s", "2 min 5 s" or "1 h 3 min"
    function secs(i,   s) { s = 0
      for (; i <= NF; i += 2) { if ($(i+1) == "s") return s + $i; if ($(i+1) == "min") s += 60 * $i
                                else if ($(i+1) == "h") s += 3600 * $i; else return s } return s }
    /^step / { s = $2; for (i = 1; i <= NF; ++i) if ($i == "wall") w = secs(i + 1); if (!n++) { s0 = s; w0 = w } }
    END { if (n < 2) { print "too few progress lines"; exit 1 }
          r = (s - s0) / (w - w0); ps = r * np;
          printf "threads %d: %d particles, %.4f s/step, %.3g particle-steps/s, %.3g per core\n", t, np, 1 / r, ps, ps / t }'
  rm -rf "$out"
done
