# shellcheck shell=bash disable=SC2034  # the variables are for the scripts that source this
# Sourced by the paired-round benchmarks (bench/tls.sh, http.sh, mqtt.sh) after
# `cd` to the source tree, with their arguments: [BUILD_DIR] [ROUNDS] [SECONDS].
# Sets build, rounds, seconds, bridged, load, work (a temporary directory) and pids
# (processes killed at exit, with the directory removed); gives free_port, field, median,
# wait_for_port and start_fed_daemon.
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

wait_for_port() {  # port, name: the daemon `name` listens on `port`, or its log and exit
  for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/"$1") 2>/dev/null && return; sleep 0.05; done
  echo "the daemon did not start:"; cat "$work/$2.log"; exit 1
}
# A daemon with D1 (a UniGEN-CHP) on the feed transport and FC4 on `modbus`; `extra`, a
# YAML line (an mqtt or sparkplug section), or nothing for the daemon without it.
start_fed_daemon() {  # name, modbus port, feed port, extra
  local name=$1 modbus=$2 feed=$3 extra=${4:-}
  {
    echo "unimabus: { transport: feed, listen: 127.0.0.1:$feed }"
    echo "modbus: { tcp: { listen: 127.0.0.1, port: $modbus, max_clients: 256 } }"
    echo "banks: { D1: 0x1100 }"
    echo "devices: { D1: { type: unigen-chp, address: 5 } }"
    echo "log: { level: warn }"
    echo "status: { socket: $work/$name.sock }"
    echo "state: { file: none }"
    if [ -n "$extra" ]; then echo "$extra"; fi
  } > "$work/$name.yaml"
  "$bridged" --config "$work/$name.yaml" > "$work/$name.log" 2>&1 &
  pids+=($!)
  wait_for_port "$modbus" "$name"
}
