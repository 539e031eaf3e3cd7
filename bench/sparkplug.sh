#!/usr/bin/env bash
# Sparkplug B's performance (issue 33, docs/performance.md), against a local mosquitto:
#   (a) a fed change to a subscriber's DDATA, p50/p99, with D1 fed 1,000 telegrams a second
#       (bench/sparkplug_probe.py latency);
#   (b) FC4 × 64 at 64 connections (unima-bench-load) on two daemons fed alike, one with a
#       sparkplug section and one without, in paired rounds whose order alternates;
#   (c) NBIRTH + DBIRTHs of four D_N, S_N and A, B, C, W, X (config/examples/four-devices.yaml
#       on the feed transport): their bytes, and the time from an NCMD rebirth to the last
#       DBIRTH at a subscriber (bench/sparkplug_probe.py births).
# Usage: bench/sparkplug.sh [BUILD_DIR] [ROUNDS] [SECONDS]   (default build-release 5 3)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/paired_rounds.sh
# shellcheck disable=SC2016  # expanded at exit
at_exit+=('[ -f "$work/broker.pid" ] && kill "$(cat "$work/broker.pid")" 2>/dev/null')
broker=$(free_port)
printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\nuser %s\npid_file %s\nlog_dest none\n' \
  "$broker" "$(id -un)" "$work/broker.pid" > "$work/broker.conf"
mosquitto -d -c "$work/broker.conf" 2>/dev/null
for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/"$broker") 2>/dev/null && break; sleep 0.05; done
sparkplug_section="sparkplug: { broker: 'mqtt://127.0.0.1:$broker', client_id: bench-sp, group_id: bench, edge_node_id: edge }"

with=$(free_port); without=$(free_port); feed_with=$(free_port); feed_without=$(free_port)
# report.min_interval 10 ms: (a) measures a change's way to the host, not the default
# 100 ms of pacing a probe every 20 ms would mostly wait for (docs/performance.md).
start_fed_daemon with "$with" "$feed_with" "$sparkplug_section"$'\n'"report: { min_interval: 10ms }"
start_fed_daemon without "$without" "$feed_without"
sleep 1

# (a) first, the host alone on the feed.
latency=$(python3 bench/sparkplug_probe.py latency --feed-port "$feed_with" --broker "$broker" \
  --topic spBv1.0/bench/DDATA/edge/D1 --seconds "$(python3 -c "print(max(2, 4 * $seconds))")")

# (b)
total=$(python3 -c "print(int(2 * $rounds * ($seconds + 0.5) * 2 + 10))")
python3 bench/mqtt_feeder.py --feed-port "$feed_with" --seconds "$total" > /dev/null &
pids+=($!)
python3 bench/mqtt_feeder.py --feed-port "$feed_without" --seconds "$total" > /dev/null &
pids+=($!)
sleep 1
rps() { "$load" --port "$1" --connections 64 --function 4 --address 4352 --quantity 64 --duration "$seconds" --warmup 0.5 --json | field rps; }
r=(); a_all=(); b_all=()
for round in $(seq "$rounds"); do
  if [ $((round % 2)) = 1 ]; then a=$(rps "$with"); b=$(rps "$without")
  else b=$(rps "$without"); a=$(rps "$with"); fi
  a_all+=("$a"); b_all+=("$b"); r+=("$(python3 -c "print($a / $b)")")
done
throughput="$(median "${a_all[@]}") $(median "${b_all[@]}") $(median "${r[@]}")"

# (c) the example's four devices on the feed transport, nothing fed: each D_N and S_N is
# born off-line (its metrics null, a DDEATH after it), as a host first learns them.
four=$(free_port); feed_four=$(free_port)
sed -e "s/^  transport: sim/  transport: feed\n  listen: 127.0.0.1:$feed_four/" -e '/^  sim:/d' \
    -e "s/port: 5020/port: $four/" config/examples/four-devices.yaml > "$work/four.yaml"
{
  echo "log: { level: warn }"
  echo "status: { socket: $work/four.sock }"
  echo "state: { file: none }"
  echo "${sparkplug_section/client_id: bench-sp, group_id: bench, edge_node_id: edge/client_id: bench-four, group_id: bench, edge_node_id: four}"
} >> "$work/four.yaml"
"$bridged" --config "$work/four.yaml" > "$work/four.log" 2>&1 &
pids+=($!)
wait_for_port "$four" four
sleep 1
births=$(python3 bench/sparkplug_probe.py births --broker "$broker" --group bench --node four --rounds "$rounds")

python3 - "$rounds" "$throughput" "$latency" "$births" <<'PY'
import json, sys
n, throughput, latency, births = sys.argv[1:5]
w, wo, ratio = throughput.split()
latency, births = json.loads(latency), json.loads(births)
print(f"| measure | figure | target |")
print("|---|---|---|")
print(f"| fed change → subscriber's DDATA, ms, p50 / p99 / max (D1 fed {latency['per_second']:,} telegrams/s) "
      f"| {latency.get('p50_ms')} / {latency.get('p99_ms')} / {latency.get('max_ms')} | p99 ≤ 20 |")
print(f"| the bridge's share: fed change → the DDATA's timestamp, ms, p50 / p99 | {latency.get('bridge_p50_ms')} / {latency.get('bridge_p99_ms')} | |")
print(f"| probes seen / sent; DDATA received | {latency['seen']} / {latency['probes']}; {latency['ddata']} | |")
print(f"| FC4 × 64, 64 connections, requests/s, with / without Sparkplug (median of {n} paired rounds) "
      f"| {float(w):,.0f} / {float(wo):,.0f}, ratio {ratio} | ratio ≥ 0.95 |")
print(f"| NBIRTH + DBIRTHs, bytes ({', '.join(births.get('devices', []))}; {births.get('metrics')} metrics) "
      f"| {births.get('bytes')} | < 65,536 |")
print(f"| NCMD rebirth → last DBIRTH at the subscriber, ms, median / max of {n} | {births.get('median_ms')} / {births.get('max_ms')} | ≤ 100 |")
PY
