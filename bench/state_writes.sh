#!/usr/bin/env bash
# Acknowledged function-6 writes per second with the state file on this machine's disk
# (SPEC §10, docs/performance.md), beside the same daemon with `state: { file: none }` in
# the same run: 1 client (one fdatasync per write) and 8 clients (group commit: the writes
# of one turn of the loop share one fdatasync). Paired rounds, medians, ratios.
# Usage: bench/state_writes.sh [BUILD_DIR] [ROUNDS] [SECONDS]   (default build-release 3 3)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-release}
rounds=${2:-3}
seconds=${3:-3}
bridged=$build/bin/unima-bridged
load=$build/bench/unima-bench-load
[ -x "$load" ] || load=$(find "$build" -name unima-bench-load -type f | head -1)
# On the disk, not in a tmpfs: the figure is about a real fdatasync.
work=$(mktemp -d "${STATE_BENCH_DIR:-$PWD/$build}/state-bench.XXXXXX")
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
port=$((20000 + RANDOM % 10000))

run_daemon() {  # $1: the state section
  cat > "$work/bridge.yaml" <<YAML
unimabus: { transport: sim }
modbus: { tcp: { listen: 127.0.0.1, port: $port, max_clients: 64 } }
log: { level: warn }
status: { socket: $work/control.sock }
$1
YAML
  "$bridged" --config "$work/bridge.yaml" > "$work/daemon.log" 2>&1 &
  pid=$!
  for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/$port) 2>/dev/null && return; sleep 0.05; done
  echo "the daemon did not start:"; cat "$work/daemon.log"; exit 1
}

writes_per_second() {  # $1: connections [$2...: more arguments of the load]
  local connections=$1; shift
  "$load" --port "$port" --connections "$connections" --function 6 --address 12288 --value 1234 "$@" \
          --duration "$seconds" --warmup 0.5 --json | python3 -c 'import json,sys; print(round(json.load(sys.stdin)["rps"]))'
}

declare -A results
for round in $(seq "$rounds"); do
  for variant in state none; do
    if [ $variant = state ]; then run_daemon "state: { file: $work/bridge.state }"; else run_daemon "state: { file: none }"; fi
    for clients in 1 8; do results[$variant,$clients]+="$(writes_per_second $clients) "; done
    # Reads of bank C (16 registers), which the state file must not slow down.
    results[$variant,reads]+="$(writes_per_second 8 --function 4 --address 4128 --quantity 16) "
    if [ $variant = state ]; then
      syncs=$(python3 - "$work/control.sock" <<'PY'
import json, socket, sys
s = socket.socket(socket.AF_UNIX); s.connect(sys.argv[1])
data = b""
while chunk := s.recv(65536): data += chunk
st = json.loads(data)["state"]; print(st["records"], st["syncs"])
PY
)
      results[syncs]+="$syncs; "
    fi
    kill "$pid"; wait "$pid" 2>/dev/null || true
  done
done

median() { tr ' ' '\n' | grep -v '^$' | sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
echo "acknowledged fn-6 writes/s, $rounds rounds of ${seconds}s, medians (state file on $(df -T "$work" | awk 'NR==2 {print $2}'))"
for clients in 1 8; do
  s=$(echo "${results[state,$clients]}" | median); n=$(echo "${results[none,$clients]}" | median)
  printf "  %d client(s): state file %8d/s   without %8d/s   ratio %.3f\n" "$clients" "$s" "$n" "$(echo "$s / $n" | bc -l)"
done
s=$(echo "${results[state,reads]}" | median); n=$(echo "${results[none,reads]}" | median)
printf "  reads (fn 4 x 16, 8 clients): state file %8d/s   without %8d/s   ratio %.3f\n" "$s" "$n" "$(echo "$s / $n" | bc -l)"
echo "  records and syncs per state round: ${results[syncs]}"
