#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (unit and integration), then builds
# the arm64 package and runs its unit tests and daemon under qemu (scripts/package.sh), then
# each fuzz target for a few seconds in a clang tree of its own (scripts/fuzz.sh, label `fuzz`),
# then the short run of the benchmark harness (label `bench`) on its own, so nothing
# competes with it for the CPUs; it checks that the harness works, never how fast anything
# is. Says how long each phase took, and lists them all at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/phases.sh
build_dir=${BUILD_DIR:-build}
phase install scripts/install-deps.sh
scripts/build.sh "$@"
# The cross-built packages' tests (tests/packaging/CMakeLists.txt) are left out here: arm64's
# is the next phase, armhf's runs on request (`ctest -L armhf`).
phase tests ctest --test-dir "$build_dir" --output-on-failure -j 2 -LE '^(bench|arm64|armhf)$'
# The arm64 package (the boxes' usual architecture) cross-built in build-arm64/, its unit
# tests and the daemon run under qemu; it installs the cross compiler and the arm64
# libraries when they are missing. Its tree is build-arm64/ whatever BUILD_DIR names.
# UNIMA_SKIP_CROSS=1 leaves it out (a quick local run; tests/packaging/first_minutes.sh,
# whose stand-in cmake builds no package).
if [ -z "${UNIMA_SKIP_CROSS:-}" ]; then
  phase arm64 env -u BUILD_DIR scripts/package.sh arm64 --test
fi
# A short run: it proves the targets build and find nothing in their seeds and a few
# seconds past them; the long runs are in docs/fuzzing.md.
FUZZ_SECONDS=${FUZZ_SECONDS:-5} scripts/fuzz.sh
phase bench ctest --test-dir "$build_dir" --output-on-failure -L bench
