#!/usr/bin/env bash
# One command on a fresh Debian 12 machine: installs the dependencies, builds Release and runs
# the whole default test suite (labels unit, validation, extreme). Then regenerates
# build/validation.md from the validation records (docs/validation.md is refreshed with
# `python3 scripts/make_validation_table.py build`).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
BUILD_DIR=${BUILD_DIR:-build}
cd "$BUILD_DIR"
# One OpenMP thread per test: ctest runs as many tests at once as there are cores, and
# oversubscribed OpenMP barriers spin (orders of magnitude slower on a loaded machine).
OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} ctest -LE long --output-on-failure -j "${JOBS:-$(nproc)}" --timeout 900
python3 ../scripts/make_validation_table.py . validation.md || true
