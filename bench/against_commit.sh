#!/usr/bin/env bash
# This tree's unima-bridged against a fixed older commit's (issue 38: bf83827, the daemon
# before the services step, is the plain path's reference), both built alike:
#   instructions per FC4 request by callgrind (bench/instructions.py), which a busy machine
#   does not disturb, then requests/s in paired rounds (bench/run_bench.py --other-bridged),
#   which it does — read those with the load average printed beside them.
# The commit is checked out in a git worktree under build-commits/ and only its daemon is
# built there; the build is kept for the next run.
# Usage: bench/against_commit.sh [COMMIT] [BUILD_DIR] [ROUNDS]   (default bf83827 build-release 7)
set -euo pipefail
cd "$(dirname "$0")/.."
commit=$(git rev-parse --short "${1:-bf83827}")
build=${2:-build-release}
rounds=${3:-7}
type=$(sed -n 's/^CMAKE_BUILD_TYPE:STRING=//p' "$build/CMakeCache.txt")
tree=build-commits/$commit
if [ ! -d "$tree" ]; then git worktree add --detach "$tree" "$commit"; fi
cmake -S "$tree" -B "$tree/build" -DCMAKE_BUILD_TYPE="$type" -DUNIMA_BUILD_TESTS=OFF >/dev/null
cmake --build "$tree/build" -j "$(nproc)" --target unima-bridged
other=$tree/build/bin/unima-bridged
python3 bench/instructions.py --load "$build/bench/unima-bench-load" "$commit=$other" "this=$build/bin/unima-bridged"
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 bench/run_bench.py --build-dir "$build" --other-bridged "$other" --rounds "$rounds" --duration 2 --depths 1 \
  --no-callgrind --no-strace
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
