#!/usr/bin/env bash
# Runs one libFuzzer target for a bounded time (CTest label `fuzz`, docs/fuzzing.md).
#   run_fuzz_target.sh TARGET SECONDS SEED_CORPUS WORK_DIR [libFuzzer options...]
# The seeds are copied into WORK_DIR/corpus, where libFuzzer adds what it finds; inputs
# found by earlier runs stay there, so each run goes on from the last. A crash, a leak, a
# timeout or a broken invariant exits non-zero and leaves the input in WORK_DIR/findings/.
set -euo pipefail
target=$1 seconds=$2 seeds=$3 work=$4
shift 4
mkdir -p "$work/corpus" "$work/findings"
cp -n "$seeds"/* "$work/corpus/"
# One process, one job: the run takes one core. -timeout: an input that takes seconds
# is a finding (a hang), not a slow input.
exec "$target" -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$work/findings/" "$@" "$work/corpus"
