#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang into build-fuzz/ (or $FUZZ_BUILD_DIR)
# and runs each for FUZZ_SECONDS (default 10) over a copy of its seed corpus: CTest label
# `fuzz` (docs/fuzzing.md). Extra arguments go to ctest, e.g. `-R feed`. Inputs found stay
# in build-fuzz/fuzz/runs/<target>/, so the next run goes on from there.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v clang++ >/dev/null; then
  echo "fuzz: clang++ is not installed (scripts/install-deps.sh installs it); nothing fuzzed" >&2
  exit 1
fi
build_dir=${FUZZ_BUILD_DIR:-build-fuzz}
jobs=${FUZZ_JOBS:-$(nproc)}
. scripts/phases.sh
. scripts/generator.sh
phase "fuzz configure" cmake -S . -B "$build_dir" -DCMAKE_CXX_COMPILER=clang++ -DUNIMA_FUZZ=ON \
  -DUNIMA_FUZZ_SECONDS="${FUZZ_SECONDS:-10}" >/dev/null
phase "fuzz build" cmake --build "$build_dir" -j "$jobs"
phase "fuzz run" ctest --test-dir "$build_dir" --output-on-failure -L fuzz -j "$jobs" "$@"
