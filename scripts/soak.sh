#!/usr/bin/env bash
# The soak and fault harness (issue 17, docs/operations.md "Soak and faults"): builds the
# release tree and runs scripts/soak.py against the real daemon over loopback. Minutes of
# load, kills and a full disk: not part of CI. Arguments go to soak.py, e.g.
#   scripts/soak.sh --minutes 30 --clients 500          # every phase
#   scripts/soak.sh --minutes 1 steady kill9            # some phases
# Exit status 0 when every phase held.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${SOAK_BUILD_DIR:-build-release}
. scripts/generator.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)" --target unima-bridged unima-bench-load >/dev/null
exec python3 scripts/soak.py --build "$build" "$@"
