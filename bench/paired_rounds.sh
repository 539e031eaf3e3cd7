# shellcheck shell=bash disable=SC2034  # the variables are for the scripts that source this
# Sourced by the paired-round benchmarks (bench/tls.sh, http.sh, mqtt.sh) after
# `cd` to the source tree, with their arguments: [BUILD_DIR] [ROUNDS] [SECONDS].
# Sets build, rounds, seconds, bridged, load, work (a temporary directory) and pids
# (processes killed at exit, with the directory removed); gives free_port, field, median.
build=${1:-build-release}
rounds=${2:-5}
seconds=${3:-3}
bridged=$build/bin/unima-bridged
load=$(find "$build" -name unima-bench-load -type f | head -1)
work=$(mktemp -d)
pids=()
at_exit=()  # more cleanup, run first
cleanup() {
  local c p
  for c in "${at_exit[@]}"; do eval "$c" || true; done
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT

free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
field() { python3 -c "import json,sys; print(json.load(sys.stdin)['$1'])"; }
median() { python3 -c 'import sys,statistics; print(round(statistics.median(float(x) for x in sys.argv[1:]), 3))' "$@"; }
