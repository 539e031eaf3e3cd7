#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (unit and integration), then the
# short run of the benchmark harness (label `bench`) on its own, so nothing competes with
# it for the CPUs; it checks that the harness works, never how fast anything is.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh "$@"
ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -j 2 -LE bench
ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -L bench
