#!/usr/bin/env bash
# Builds and runs the master benchmark (bench/master): at most a minute. Arguments go to
# master_bench, e.g. --seconds 20 or --report FILE.
set -euo pipefail
cd "$(dirname "$0")/../.."
build="${BUILD_DIR:-build}"
cmake -S . -B "$build" -DUNIMA_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j 2 --target master_bench
"$build/bench/master/master_bench" "$@"
