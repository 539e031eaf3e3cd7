#!/usr/bin/env bash
# MQTT's cost to Modbus (issue 19, docs/performance.md): two daemons on the feed transport,
# one publishing to a mosquitto broker and one without MQTT, both fed a telegram that
# changes every D1 register 1,000 times a second (bench/mqtt_feeder.py); FC4 × 64 at 64
# connections (unima-bench-load) in paired rounds whose order alternates. Then the
# latency from a fed telegram to a subscriber's document, and the same pairs with the
# broker gone (the client retrying in the background).
# Usage: bench/mqtt.sh [BUILD_DIR] [ROUNDS] [SECONDS]   (default build-release 5 3)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/paired_rounds.sh
# shellcheck disable=SC2016  # expanded at exit
at_exit+=('[ -f "$work/broker.pid" ] && kill "$(cat "$work/broker.pid")" 2>/dev/null')
broker=$(free_port)
start_broker() {
  printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\nuser %s\npid_file %s\nlog_dest none\n' \
    "$broker" "$(id -un)" "$work/broker.pid" > "$work/broker.conf"
  mosquitto -d -c "$work/broker.conf" 2>/dev/null
  for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/"$broker") 2>/dev/null && return; sleep 0.05; done
  echo "the broker did not start"; exit 1
}
stop_broker() { kill "$(cat "$work/broker.pid")"; rm -f "$work/broker.pid"; sleep 0.3; }

start_broker
with=$(free_port); without=$(free_port); feed_with=$(free_port); feed_without=$(free_port)
start_fed_daemon with "$with" "$feed_with" "mqtt: { broker: 'mqtt://127.0.0.1:$broker', client_id: bench, topic: bench/site }"
start_fed_daemon without "$without" "$feed_without"
total=$(python3 -c "print(int(2 * $rounds * ($seconds + 0.5) * 2 + 10))")
python3 bench/mqtt_feeder.py --feed-port "$feed_with" --seconds "$total" > "$work/feed-with.json" &
feeders=($!)
python3 bench/mqtt_feeder.py --feed-port "$feed_without" --seconds "$total" > "$work/feed-without.json" &
feeders+=($!)
pids+=("${feeders[@]}")
sleep 1

rps() { "$load" --port "$1" --connections 64 --function 4 --address 4352 --quantity 64 --duration "$seconds" --warmup 0.5 --json | field rps; }
paired() {  # prints: median with, median without, median ratio
  local r=() a_all=() b_all=()
  for round in $(seq "$rounds"); do
    if [ $((round % 2)) = 1 ]; then a=$(rps "$with"); b=$(rps "$without")
    else b=$(rps "$without"); a=$(rps "$with"); fi
    a_all+=("$a"); b_all+=("$b"); r+=("$(python3 -c "print($a / $b)")")
  done
  echo "$(median "${a_all[@]}") $(median "${b_all[@]}") $(median "${r[@]}")"
}

read -r connected_with connected_without connected_ratio <<< "$(paired)"
# Latency: a feeder of its own for a few seconds, the load off.
for p in "${feeders[@]}"; do kill "$p" 2>/dev/null || true; done
latency=$(python3 bench/mqtt_feeder.py --feed-port "$feed_with" --seconds 4 --broker "$broker" --topic bench/site/D1)
python3 bench/mqtt_feeder.py --feed-port "$feed_with" --seconds "$total" > /dev/null &
pids+=($!)
python3 bench/mqtt_feeder.py --feed-port "$feed_without" --seconds "$total" > /dev/null &
pids+=($!)
stop_broker
sleep 1
read -r gone_with gone_without gone_ratio <<< "$(paired)"

python3 - "$rounds" "$connected_with" "$connected_without" "$connected_ratio" "$gone_with" "$gone_without" "$gone_ratio" "$latency" <<'PY'
import json, sys
n, cw, co, cr, gw, go, gr, latency = sys.argv[1:9]
latency = json.loads(latency)
print(f"| measure (feed changing all of D1 1,000 times a second) | with MQTT | without MQTT | ratio (median of {n} paired rounds) |")
print("|---|---|---|---|")
print(f"| FC4 × 64, 64 connections, requests/s, broker connected | {float(cw):,.0f} | {float(co):,.0f} | {cr} |")
print(f"| the same, broker unreachable (client retrying) | {float(gw):,.0f} | {float(go):,.0f} | {gr} |")
print(f"| fed telegram → subscriber's D1 document, ms, p50 / p99 | {latency.get('p50_ms')} / {latency.get('p99_ms')} | | |")
print(f"| documents received / telegrams fed in that run | {latency.get('documents')} / {latency.get('telegrams')} | | |")
PY
