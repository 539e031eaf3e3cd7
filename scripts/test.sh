#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (unit, integration, packaging), then
# each fuzz target for a few seconds in a clang tree of its own (scripts/fuzz.sh, label
# `fuzz`), then the short run of the benchmark harness (label `bench`) after the other
# tests; it checks that the harness works, never how fast anything is. Says how long each
# phase took, and lists them all at the end. The arm64 package's path (cross build, unit
# tests and daemon under qemu) is `scripts/package.sh arm64 --test`, which CI runs after
# this (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/phases.sh
build_dir=${BUILD_DIR:-build}
phase install scripts/install-deps.sh
scripts/build.sh "$@"
# The cross-built packages' tests (tests/packaging/CMakeLists.txt) are left out here: arm64's
# runs in CI after this script (.ci/run), armhf's on request (`ctest -L armhf`). Three at a
# time on two cores: the integration tests spend most of their time waiting on the daemon.
phase tests ctest --test-dir "$build_dir" --output-on-failure -j 3 -LE '^(bench|arm64|armhf)$'
# A short run: it proves the targets build and find nothing in their seeds and a few
# seconds past them; the long runs are in docs/fuzzing.md.
FUZZ_SECONDS=${FUZZ_SECONDS:-5} scripts/fuzz.sh
# Two at a time: they check the harness, and none of them judges a speed.
phase bench ctest --test-dir "$build_dir" --output-on-failure -j 2 -L bench
