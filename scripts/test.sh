#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (unit and integration), then each
# fuzz target for a few seconds in a clang tree of its own (scripts/fuzz.sh, label `fuzz`),
# then the short run of the benchmark harness (label `bench`) on its own, so nothing
# competes with it for the CPUs; it checks that the harness works, never how fast anything
# is. Says how long each phase took, and lists them all at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/phases.sh
build_dir=${BUILD_DIR:-build}
phase install scripts/install-deps.sh
scripts/build.sh "$@"
phase tests ctest --test-dir "$build_dir" --output-on-failure -j 2 -LE bench
# A short run: it proves the targets build and find nothing in their seeds and a few
# seconds past them; the long runs are in docs/fuzzing.md.
FUZZ_SECONDS=${FUZZ_SECONDS:-5} scripts/fuzz.sh
phase bench ctest --test-dir "$build_dir" --output-on-failure -L bench
