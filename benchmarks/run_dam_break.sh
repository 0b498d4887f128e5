#!/usr/bin/env bash
# Full-step speed of the fluid solver on the 3D dam break (benchmarks/scenes/dam_break_3d.yaml,
# 176,868 particles: 80,400 water + 96,468 wall), 1 and 2 threads: particle-steps per second,
# the figure DualSPHysics' CPU solver is compared by (~1.3e5 per core on these machines).
# Usage: bash benchmarks/run_dam_break.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
exec bash benchmarks/run_step_rate.sh benchmarks/scenes/dam_break_3d.yaml "${1:-build}"
