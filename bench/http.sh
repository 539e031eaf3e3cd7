#!/usr/bin/env bash
# The HTTP server's cost to Modbus (issue 20, docs/performance.md): two daemons on the
# simulated plant, one with `http` and one without, FC4 × 64 at 64 connections
# (unima-bench-load) in paired rounds whose order alternates; during each round of the
# HTTP daemon a front page listens to /api/events and Prometheus' scrape is imitated
# (GET /metrics every second) by bench/http_clients.py. Reports the requests/s ratio
# (median), what the live feed sent against full pictures, and the HTTP daemon's peak RSS.
# Usage: bench/http.sh [BUILD_DIR] [ROUNDS] [SECONDS]   (default build-release 5 3)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/paired_rounds.sh
start_daemon() {  # name, modbus port, http port (0: none)
  local name=$1 modbus=$2 http=$3
  {
    echo "unimabus: { transport: sim, sim: { seed: 1, period: 1s, io_modules: [1] } }"
    echo "modbus: { tcp: { listen: 127.0.0.1, port: $modbus, max_clients: 256 } }"
    echo "devices: { D1: { type: unigen-chp, address: 5 }, D2: { type: usc, address: 5 }, D3: { type: uvr, address: 5 } }"
    echo "log: { level: warn }"
    echo "status: { socket: $work/$name.sock }"
    echo "state: { file: none }"
    if [ "$http" != 0 ]; then echo "http: { listen: 127.0.0.1, port: $http }"; fi
  } > "$work/$name.yaml"
  "$bridged" --config "$work/$name.yaml" > "$work/$name.log" 2>&1 &
  pids+=($!)
  if [ "$name" = served ]; then served_pid=$!; fi
  for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/"$modbus") 2>/dev/null && return; sleep 0.05; done
  echo "the daemon did not start:"; cat "$work/$name.log"; exit 1
}

with=$(free_port); without=$(free_port); http=$(free_port)
start_daemon served "$with" "$http"
start_daemon bare "$without" 0

rps() { "$load" --port "$1" --connections 64 --function 4 --address 4352 --quantity 64 --duration "$seconds" --warmup 0.5 --json | field rps; }
rps_with_page() {  # the page and the scraper run for the whole round
  python3 bench/http_clients.py --port "$http" --seconds "$(python3 -c "print($seconds + 2)")" > "$work/clients.json" &
  local clients=$!
  sleep 0.3
  rps "$with"
  wait "$clients"
  cat "$work/clients.json" >> "$work/all-clients.json"
}

ratios=(); a_all=(); b_all=()
for round in $(seq "$rounds"); do
  if [ $((round % 2)) = 1 ]; then a=$(rps_with_page); b=$(rps "$without")
  else b=$(rps "$without"); a=$(rps_with_page); fi
  a_all+=("$a"); b_all+=("$b"); ratios+=("$(python3 -c "print($a / $b)")")
  echo "round $round: with HTTP $a, without $b" >&2
done
peak_rss_kib=$(awk '/VmHWM/ {print $2}' "/proc/$served_pid/status")
python3 - "$work/all-clients.json" "$(median "${a_all[@]}")" "$(median "${b_all[@]}")" "$(median "${ratios[@]}")" "$peak_rss_kib" "$rounds" <<'PY'
import json, sys
rounds = [json.loads(line) for line in open(sys.argv[1])]
with_http, without, ratio, peak_kib, n = sys.argv[2:7]
seconds = sum(r["seconds"] for r in rounds)
per_second = lambda *names: sum(r["bytes_by_event"].get(n, 0) for r in rounds for n in names) / seconds
full = sum(r["full_values_bytes"] for r in rounds) / len(rounds)
print(f"| measure | with HTTP (page open, /metrics every 1 s) | without HTTP | ratio (median of {n} paired rounds) |")
print("|---|---|---|---|")
print(f"| FC4 × 64, 64 connections, requests/s | {float(with_http):,.0f} | {float(without):,.0f} | {ratio} |")
print(f"| live feed to the page: values and panel that changed, bytes/s | {per_second('registers', 'panel'):,.0f} | | |")
print(f"| the same as full pictures 4 times a second, bytes/s | {4 * full:,.0f} | | |")
print(f"| live feed to the page: monitor lines (at most 25 per event), bytes/s | {per_second('monitor'):,.0f} | | |")
print(f"| /metrics scrapes answered | {sum(r['scrapes'] for r in rounds)} | | |")
print(f"| peak RSS of the daemon with HTTP, MiB | {int(peak_kib) / 1024:.1f} | | |")
PY
