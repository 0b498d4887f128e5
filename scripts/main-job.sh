#!/usr/bin/env bash
# One command on a fresh Debian 12 machine: installs the dependencies, builds Release and runs the
# main sample. Each run writes to a new folder runs/<sample>-<date-time>, so no earlier result is
# overwritten. Usage: bash scripts/main-job.sh [SCENE]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
BUILD_DIR=${BUILD_DIR:-build}
# The main job: gas drainage with damage under confining stress in a 16^3 crop of the shipped
# Ketton image (samples/drainage_ketton_3d.yaml, docs/drainage.md).
SCENE=${1:-samples/drainage_ketton_3d.yaml}
[ -f "$SCENE" ] || SCENE=""
[ -n "$SCENE" ] || { echo "main-job: no sample scene found" >&2; exit 1; }
OUT="runs/$(basename "$SCENE" .yaml)-$(date +%Y%m%d-%H%M%S)"
echo "main-job: running $SCENE into $OUT"
"$BUILD_DIR/poresph" run "$SCENE" --out "$OUT" --threads "$(nproc)"
# Pictures: the standard views (3D phases, xy/yz cuts of damage, pressure and the largest
# principal stress) and the drainage curves (porosity, saturation, damaged fraction vs time).
if /usr/bin/python3 -c "import vtk, matplotlib" 2>/dev/null; then
  /usr/bin/python3 scripts/render_views.py "$OUT" --out "$OUT/views" || echo "main-job: render_views failed" >&2
  /usr/bin/python3 scripts/plot_timeseries.py "$OUT/timeseries.csv" --out "$OUT/views/drainage.png" || echo "main-job: plot_timeseries failed" >&2
fi
echo "main-job: results in $OUT (open $OUT/results.pvd in ParaView; pictures in $OUT/views)"
