#!/usr/bin/env bash
# Full-step speed of the fluid solver on the 3D dam break (benchmarks/scenes/dam_break_3d.yaml,
# 176,868 particles: 80,400 water + 96,468 wall), 1 and 2 threads: particle-steps per second,
# the figure DualSPHysics' CPU solver is compared by (~1.3e5 per core on these machines).
# Usage: bash benchmarks/run_dam_break.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
for t in 1 2; do
  out=$(mktemp -d)
  log=$("$BUILD_DIR/poresph" run benchmarks/scenes/dam_break_3d.yaml --out "$out" --force --threads "$t" 2>&1)
  # Steady rate from the progress lines: (last step - first step) / (last wall - first wall).
  echo "$log" | awk -v t="$t" '
    /^step / { s = $2; for (i = 1; i <= NF; ++i) if ($i == "wall") w = $(i+1); if (!n++) { s0 = s; w0 = w } }
    /^particles:/ { np = $2 }
    END { if (n < 2) { print "too few progress lines"; exit 1 }
          r = (s - s0) / (w - w0); ps = r * 176868;
          printf "threads %d: %.4f s/step, %.3g particle-steps/s, %.3g per core\n", t, 1 / r, ps, ps / t }'
  rm -rf "$out"
done
