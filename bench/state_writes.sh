#!/usr/bin/env bash
# Acknowledged function-6 writes per second with the state file on this machine's disk
# (SPEC §10, docs/performance.md), measured against the disk itself: each measurement of
# the daemon (1, 8 and 64 clients) is paired with a raw append+fdatasync loop in the same
# directory just before or after it (the order alternates by round), because the disk's
# sync rate moves with whatever else the machine writes. Reported, medians over rounds:
#   1 client:  writes/s and their ratio to the raw syncs/s (one write waits for one sync);
#   8, 64:     writes/s, and the daemon's fdatasyncs/s (status `state.syncs`, read during
#              the load) against the raw syncs/s: the share of the disk's sync rate used.
#   and the raw loop again while 64 clients read from the daemon: what the CPU work of that
#   many clients alone leaves of the disk's sync rate on this machine.
# On a virtual machine an idle vCPU takes up to milliseconds to wake for the interrupt that
# ends an fdatasync, so a lone raw loop, which leaves the CPUs idle while it waits, looks
# far slower than the daemon with its clients busy beside it. One busy loop per CPU in
# SCHED_IDLE keeps them awake for both and yields at once to anything else
# (STATE_BENCH_AWAKE=0: none).
# Usage: bench/state_writes.sh [BUILD_DIR] [ROUNDS] [SECONDS]   (default build-release 5 2)
# Runs about ROUNDS x 7 x (SECONDS + 1) s; loopback only. STATE_BENCH_BRIDGED=PATH measures
# another build of the daemon (e.g. the one before a change) against the same raw loop.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-release}
rounds=${2:-5}
seconds=${3:-2}
bridged=${STATE_BENCH_BRIDGED:-$build/bin/unima-bridged}
load=$build/bench/unima-bench-load
[ -x "$load" ] || load=$(find "$build" -name unima-bench-load -type f | head -1)
# On the disk, not in a tmpfs: the figure is about a real fdatasync.
work=$(mktemp -d "${STATE_BENCH_DIR:-$PWD/$build}/state-bench.XXXXXX")
pid=
spinners=()
trap '[ -z "$pid" ] || kill "$pid" 2>/dev/null || true; for s in "${spinners[@]}"; do kill "$s" 2>/dev/null || true; done; rm -rf "$work"' EXIT
# Bounded even if this script is killed: each spinner ends on its own after the run's length.
limit=$(echo "$rounds * 7 * ($seconds + 3) + 60" | bc)
for _ in $(seq "${STATE_BENCH_AWAKE:-$(nproc)}"); do chrt --idle 0 timeout "$limit" sh -c 'while :; do :; done' & spinners+=($!); done
port=$((20000 + RANDOM % 10000))
warmup=0.5

run_daemon() {
  cat > "$work/bridge.yaml" <<YAML
unimabus: { transport: sim }
modbus: { tcp: { listen: 127.0.0.1, port: $port, max_clients: 64 } }
log: { level: warn }
status: { socket: $work/control.sock }
state: { file: $work/bridge.state }
YAML
  "$bridged" --config "$work/bridge.yaml" > "$work/daemon.log" 2>&1 &
  pid=$!
  for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/$port) 2>/dev/null && [ -S "$work/control.sock" ] && return; sleep 0.05; done
  echo "the daemon did not start:"; cat "$work/daemon.log"; exit 1
}

json() { python3 -c "import json,sys; d = json.load(open(sys.argv[1])); print(d['$2'])" "$3"; }

raw() {  # prints the raw syncs/s
  python3 bench/raw_syncs.py "$work/raw" "$seconds" > "$work/raw.json"
  json "$work/raw.json" per_second "$work/raw.json"
}

daemon() {  # $1: clients; prints writes/s and the daemon's syncs/s during the load
  "$load" --port "$port" --connections "$1" --function 6 --address 12288 --value 1234 \
          --duration "$seconds" --warmup "$warmup" --json > "$work/load.json" &
  local load_pid=$!
  # The counters are read inside the measured window, away from its edges.
  python3 bench/state_syncs.py "$work/control.sock" "$(echo "$warmup + 0.1" | bc)" "$(echo "$seconds - 0.2" | bc)" \
          > "$work/syncs.json"
  wait "$load_pid"
  echo "$(json "$work/load.json" rps "$work/load.json") $(json "$work/syncs.json" syncs_per_second "$work/syncs.json")" \
       "$(json "$work/syncs.json" records_per_sync "$work/syncs.json")"
}

declare -A results
for round in $(seq "$rounds"); do
  run_daemon
  for clients in 1 8 64; do
    if [ $((round % 2)) = 1 ]; then r=$(raw); read -r w s b <<< "$(daemon $clients)"
    else read -r w s b <<< "$(daemon $clients)"; r=$(raw); fi
    results[raw]+="$r "
    results[writes,$clients]+="$w "
    results[write_ratio,$clients]+="$(echo "$w / $r" | bc -l) "
    results[sync_ratio,$clients]+="$(echo "$s / $r" | bc -l) "
    results[batch,$clients]+="$b "
  done
  "$load" --port "$port" --connections 64 --function 4 --address 4128 --quantity 16 \
          --duration "$(echo "$seconds + 1" | bc)" --warmup 0 > /dev/null &
  readers=$!
  sleep 0.5
  results[raw_beside]+="$(raw) "
  wait "$readers"
  kill "$pid"; wait "$pid" 2>/dev/null || true; pid=
done

median() { python3 -c 'import sys,statistics; print(statistics.median(float(x) for x in sys.argv[1:]))' "$@"; }
range() { python3 -c 'import sys; v = [float(x) for x in sys.argv[1:]]; print(f"{min(v):.2f}-{max(v):.2f}")' "$@"; }
# shellcheck disable=SC2086  # the lists are split on purpose
{
  raw_rate=$(median ${results[raw]})
  echo "state file: $rounds rounds of ${seconds}s, medians, each measurement paired with a raw loop (on $(df -T "$work" | awk 'NR==2 {print $2}'))"
  printf "  raw append+fdatasync:  %6.0f syncs/s  %5.0f us per sync\n" "$raw_rate" "$(echo "1000000 / $raw_rate" | bc -l)"
  w=$(median ${results[writes,1]})
  printf "  1 client:   %6.0f writes/s  %5.0f us per write   writes/raw syncs %.2f (rounds %s)\n" "$w" \
         "$(echo "1000000 / $w" | bc -l)" "$(median ${results[write_ratio,1]})" "$(range ${results[write_ratio,1]})"
  beside=$(median ${results[raw_beside]})
  printf "  raw loop while 64 clients read: %6.0f syncs/s  (%.2f of the raw rate above)\n" "$beside" \
         "$(echo "$beside / $raw_rate" | bc -l)"
  for clients in 8 64; do
    printf "  %2d clients: %6.0f writes/s  %4.1f records per sync   sync rate used %.2f (rounds %s)\n" "$clients" \
           "$(median ${results[writes,$clients]})" "$(median ${results[batch,$clients]})" \
           "$(median ${results[sync_ratio,$clients]})" "$(range ${results[sync_ratio,$clients]})"
  done
}
