#!/usr/bin/env bash
# Builds and runs the master benchmark (bench/master): at most a minute. A release build in
# its own build directory (BUILD_DIR, default build-bench; BUILD_TYPE, default Release), so
# that a debug or sanitizer build's timing does not count. Arguments go to master_bench,
# e.g. --seconds 20, --report FILE or --frames FILE (the simulator's frame log).
set -euo pipefail
cd "$(dirname "$0")/../.."
build="${BUILD_DIR:-build-bench}"
cmake -S . -B "$build" -DUNIMA_BUILD_BENCH=ON -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" >/dev/null
cmake --build "$build" -j 2 --target master_bench
"$build/bench/master/master_bench" "$@"
