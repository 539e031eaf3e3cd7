#!/usr/bin/env bash
# Builds and runs the gateway benchmark (bench/gateway) in full: 5 paired rounds of 4 s
# runs, a few minutes. A release build in its own build directory (BUILD_DIR, default
# build-bench; BUILD_TYPE, default Release). MBUSD=/path/to/mbusd runs mbusd beside it
# (built from https://github.com/3cky/mbusd for the bench only: docs/performance.md).
# Arguments go to gateway_bench, e.g. --rounds 9, --seconds 8, --report FILE; --lines runs
# the several-lines bench (one daemon, two RS-485 lines) instead.
set -euo pipefail
cd "$(dirname "$0")/../.."
build="${BUILD_DIR:-build-bench}"
cmake -S . -B "$build" -DUNIMA_BUILD_BENCH=ON -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" >/dev/null
cmake --build "$build" -j 2 --target gateway_bench
mbusd=()
if [[ -n "${MBUSD:-}" ]]; then mbusd=(--mbusd "$MBUSD"); fi
"$build/bench/gateway/gateway_bench" --load "$(find "$build" -name unima-bench-load -type f | head -1)" "${mbusd[@]}" "$@"
