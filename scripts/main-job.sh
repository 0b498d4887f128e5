#!/usr/bin/env bash
# One command on a fresh Debian 12 machine: installs the dependencies, builds Release and runs the
# main sample. Each run writes to a new folder runs/<sample>-<date-time>, so no earlier result is
# overwritten. Usage: bash scripts/main-job.sh [SCENE]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
BUILD_DIR=${BUILD_DIR:-build}
# The main job is the drainage-with-damage sample once it exists; until then the best available.
SCENE=${1:-}
if [ -z "$SCENE" ]; then
  # (capillary entry: gas displacing water from a slit above its entry pressure, i.e. drainage
  # of one pore throat)
  for candidate in samples/drainage_damage.yaml samples/fluid_capillary_entry.yaml samples/fluid_poiseuille.yaml; do
    if [ -f "$candidate" ]; then SCENE=$candidate; break; fi
  done
fi
[ -n "$SCENE" ] || { echo "main-job: no sample scene found" >&2; exit 1; }
OUT="runs/$(basename "$SCENE" .yaml)-$(date +%Y%m%d-%H%M%S)"
echo "main-job: running $SCENE into $OUT"
"$BUILD_DIR/poresph" run "$SCENE" --out "$OUT" --threads "$(nproc)"
echo "main-job: results in $OUT (open $OUT/results.pvd in ParaView)"
