#!/usr/bin/env bash
# Builds and runs every test, the long validation studies included, then regenerates
# docs/validation.md from the records. Takes much longer than scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
BUILD_DIR=${BUILD_DIR:-build}
(cd "$BUILD_DIR" && OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} ctest --output-on-failure -j "${JOBS:-$(nproc)}" --timeout 3600)
python3 scripts/make_validation_table.py "$BUILD_DIR" docs/validation.md
