#!/usr/bin/env bash
# Configures and builds into build/ (or $BUILD_DIR), with as many jobs as CPUs. Extra
# arguments go to cmake's configure; BUILD_TARGETS (space-separated) builds only those
# targets, as the demo does. Each step says how long it took.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/phases.sh
. scripts/generator.sh
build_dir=${BUILD_DIR:-build}
targets=()
for target in ${BUILD_TARGETS:-}; do targets+=(--target "$target"); done
phase configure cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-RelWithDebInfo}" "$@" >/dev/null
phase build cmake --build "$build_dir" -j "$(nproc)" "${targets[@]}"
