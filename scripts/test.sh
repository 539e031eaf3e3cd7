#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (unit and integration), then each
# fuzz target for a few seconds in a clang tree of its own (scripts/fuzz.sh, label `fuzz`),
# then the short run of the benchmark harness (label `bench`) on its own, so nothing
# competes with it for the CPUs; it checks that the harness works, never how fast anything
# is.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh "$@"
ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -j 2 -LE bench
# A short run: it proves the targets build and find nothing in their seeds and a few
# seconds past them; the long runs are in docs/fuzzing.md.
FUZZ_SECONDS=${FUZZ_SECONDS:-5} scripts/fuzz.sh
ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -L bench
