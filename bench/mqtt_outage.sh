#!/usr/bin/env bash
# MQTT history through a broker outage (issue 32, docs/performance.md): two daemons on the
# feed transport, both fed a telegram that changes every D1 register 1,000 times a second
# (bench/mqtt_feeder.py); one publishes to a local mosquitto with the history buffer
# (mqtt.buffer), the other has no mqtt section. The broker is killed (the client sees the
# connection close at once) and started again on the same port OUTAGE seconds later.
# During the outage: FC4 × 64 at 64 connections (unima-bench-load) in paired rounds whose
# order alternates, the MQTT daemon's VmRSS before and at the end, and the buffer's syncs
# per second from its status counter. After the restart: the history's rate as a QoS 1
# subscriber with a persistent session (mosquitto_sub, `bench/site/history/#`) receives
# it, and, for what bounds it, the same broker and subscriber fed by mosquitto_pub with
# the same window (100 in flight) and the same documents.
# Usage: bench/mqtt_outage.sh [BUILD_DIR] [ROUNDS] [SECONDS] [OUTAGE]   (default build-release 7 3 60)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/paired_rounds.sh
outage=${4:-60}
# shellcheck disable=SC2016  # expanded at exit
# stop_broker waits for its exit: it writes its sessions into $work, which goes next.
at_exit+=('[ -f "$work/broker.pid" ] && stop_broker')
broker=$(free_port)
# The broker keeps sessions over its restart, so the history subscriber misses nothing the
# daemon publishes the moment it is back; room for every queued message of a long history.
start_broker() {
  printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence true\npersistence_location %s/\nmax_queued_messages 1000000\nuser %s\npid_file %s\nlog_dest none\n' \
    "$broker" "$work" "$(id -un)" "$work/broker.pid" > "$work/broker.conf"
  mosquitto -d -c "$work/broker.conf" 2>/dev/null
  for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/"$broker") 2>/dev/null && return; sleep 0.05; done
  echo "the broker did not start"; exit 1
}
stop_broker() {  # SIGTERM: the connections close at once (and the sessions are saved)
  local pid; pid=$(cat "$work/broker.pid")
  kill "$pid"
  for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.05; done
  rm -f "$work/broker.pid"
}

# One value of the MQTT daemon's status document, e.g. mqtt.buffer.syncs.
status() {
  python3 - "$work/with.sock" "$1" <<'PY'
import json, socket, sys
s = socket.socket(socket.AF_UNIX)
s.connect(sys.argv[1])
data = b""
while chunk := s.recv(65536):
    data += chunk
value = json.loads(data)
for key in sys.argv[2].split("."):
    value = value[key]
print(json.dumps(value))
PY
}
# Waits (bounded) until the status value is `expected`; false if it never was.
wait_status() {  # key, expected, seconds
  local deadline=$((SECONDS + $3))
  while [ "$SECONDS" -lt "$deadline" ]; do [ "$(status "$1")" = "$2" ] && return 0; sleep 0.1; done
  return 1
}
rss_kib() { awk '/^VmRSS:/ { print $2 }' "/proc/$1/status"; }
cpu_ticks() { awk '{ print $14 + $15 }' "/proc/$1/stat"; }  # utime + stime
now() { date +%s.%N; }

start_broker
with=$(free_port); without=$(free_port); feed_with=$(free_port); feed_without=$(free_port)
start_fed_daemon with "$with" "$feed_with" \
  "mqtt: { broker: 'mqtt://127.0.0.1:$broker', client_id: bench, topic: bench/site, buffer: { file: $work/mqtt-buffer } }"
with_pid=${pids[-1]}
start_fed_daemon without "$without" "$feed_without"
wait_status mqtt.connected true 10 || { echo "the daemon did not connect:"; cat "$work/with.log"; exit 1; }
mosquitto_sub -c -i obench-history -q 1 -p "$broker" -t 'bench/site/history/#' -F '%U %t' > "$work/history" 2>&1 &
subscriber=$!
pids+=("$subscriber")
# The broker's longest wait for the client's retry (60 s back-off + 25 % jitter), the history, the reference.
total=$(python3 -c "print(int($outage + 4 * $rounds * ($seconds + 1) + 150))")
python3 bench/mqtt_feeder.py --feed-port "$feed_with" --seconds "$total" > /dev/null &
pids+=($!)
python3 bench/mqtt_feeder.py --feed-port "$feed_without" --seconds "$total" > /dev/null &
pids+=($!)

rps() { "$load" --port "$1" --connections 64 --function 4 --address 4352 --quantity 64 --duration "$seconds" --warmup 0.5 --json | field rps; }
# The daemons' connections and buffers made once, broker connected, before RSS is read.
rps "$with" > /dev/null; rps "$without" > /dev/null
rss_before=$(rss_kib "$with_pid")
syncs_before=$(status mqtt.buffer.syncs)
syncs_before_at=$(now)

stop_broker
outage_start=$(now)
wait_status mqtt.connected false 5 || { echo "the daemon did not see the outage"; exit 1; }
ratios=() a_all=() b_all=()
for round in $(seq "$rounds"); do
  # Only rounds that end inside the outage.
  python3 -c "import sys; sys.exit(0 if $(now) - $outage_start + 2 * ($seconds + 1) < $outage else 1)" || break
  if [ $((round % 2)) = 1 ]; then a=$(rps "$with"); b=$(rps "$without")
  else b=$(rps "$without"); a=$(rps "$with"); fi
  a_all+=("$a"); b_all+=("$b"); ratios+=("$(python3 -c "print($a / $b)")")
done
[ ${#ratios[@]} -gt 0 ] || { echo "no round fits in an outage of $outage s"; exit 1; }
python3 -c "import time; time.sleep(max(0, $outage_start + $outage - $(now)))"
outage_end=$(now)
rss_end=$(rss_kib "$with_pid")
syncs_end=$(status mqtt.buffer.syncs)
syncs_end_at=$(now)
buffered=$(status mqtt.buffer.messages)
sent_before=$(status mqtt.buffer.history_sent)

start_broker
restart=$(now)
cpu_restart=$(cpu_ticks "$with_pid")
wait_status mqtt.connected true 80 || { echo "the daemon did not reconnect:"; cat "$work/with.log"; exit 1; }
reconnected=$(now)
wait_status mqtt.buffer.messages 0 60 || { echo "the history was not delivered:"; status mqtt.buffer; exit 1; }
delivered=$(now)
cpu_delivered=$(cpu_ticks "$with_pid")
sent=$(( $(status mqtt.buffer.history_sent) - sent_before ))
# The subscriber has all of it once it holds as many as the broker acknowledged (bounded).
for _ in $(seq 100); do [ "$(wc -l < "$work/history")" -ge "$sent" ] && break; sleep 0.1; done

# The reference: the same documents through the same broker to the same subscriber, from
# mosquitto_pub with at most 100 in flight — what the broker and subscriber take.
reference_count=$(( sent > 200 ? sent : 200 ))
mosquitto_sub -p "$broker" -t bench/site/D1 -C 1 -W 5 > "$work/one-document"  # the retained live document
python3 -c "import sys; sys.stdout.write((open(sys.argv[1]).read().strip() + '\n') * int(sys.argv[2]))" \
  "$work/one-document" "$reference_count" > "$work/reference-lines"
history_lines=$(wc -l < "$work/history")
mosquitto_pub -p "$broker" -q 1 -M 100 -t bench/site/history/reference -l < "$work/reference-lines"
for _ in $(seq 100); do [ "$(wc -l < "$work/history")" -ge $((history_lines + reference_count)) ] && break; sleep 0.1; done

python3 - "$work/history" "$rounds" "${#ratios[@]}" "$(median "${a_all[@]}")" "$(median "${b_all[@]}")" "$(median "${ratios[@]}")" \
  "$outage" "$outage_start" "$outage_end" "$rss_before" "$rss_end" "$syncs_before" "$syncs_end" "$(python3 -c "print($syncs_end_at - $syncs_before_at)")" "$buffered" \
  "$restart" "$reconnected" "$delivered" "$sent" "$cpu_restart" "$cpu_delivered" "$(getconf CLK_TCK)" "${ratios[*]}" <<'PY'
import sys
(path, rounds, done_rounds, with_rps, without_rps, ratio, outage, outage_start, outage_end, rss_before, rss_end,
 syncs_before, syncs_end, syncs_seconds, buffered, restart, reconnected, delivered, sent, cpu_restart, cpu_delivered, ticks, round_ratios) = sys.argv[1:24]
history, reference = [], []
for line in open(path):
    stamp, _, topic = line.strip().partition(" ")
    try:
        (reference if topic.endswith("/reference") else history).append(float(stamp))
    except ValueError:
        pass

def rate(stamps):  # messages/s from the first to the last received, and the count
    if len(stamps) < 2 or stamps[-1] == stamps[0]:
        return 0.0
    return (len(stamps) - 1) / (stamps[-1] - stamps[0])

def pauses(stamps):  # the gaps of 1 ms or more between two messages: how many, their share of the time
    gaps = [b - a for a, b in zip(stamps, stamps[1:]) if b - a >= 0.001]
    span = stamps[-1] - stamps[0] if len(stamps) > 1 else 0
    return f"{len(gaps)} pauses ≥ 1 ms, {sum(gaps) / span * 100 if span else 0:.0f} % of the time"

def after_window(stamps):  # the same past the first 100 (the window's first burst)
    return rate(stamps[100:]) if len(stamps) > 150 else float("nan")

syncs = int(syncs_end) - int(syncs_before)
cpu = (int(cpu_delivered) - int(cpu_restart)) / int(ticks)
print(f"| measure (feed changing all of D1 1,000 times a second, broker killed for {float(outage):g} s) | figure |")
print("|---|---|")
print(f"| FC4 × 64, 64 connections, requests/s during the outage: MQTT + buffer / no mqtt (median of {done_rounds} paired rounds) "
      f"| {float(with_rps):,.0f} / {float(without_rps):,.0f} = {ratio} (rounds: {', '.join(f'{float(r):.2f}' for r in round_ratios.split())}) |")
print(f"| MQTT daemon's VmRSS, MiB: before the outage → at its end (growth) | {int(rss_before) / 1024:.1f} → "
      f"{int(rss_end) / 1024:.1f} ({(int(rss_end) - int(rss_before)) / 1024:+.1f}) |")
print(f"| buffer syncs (fdatasync) per second, counter read before the broker's kill and at the outage's end "
      f"| {syncs / float(syncs_seconds):.2f} ({syncs} in {float(syncs_seconds):.1f} s) |")
print(f"| documents buffered at the end of the outage | {buffered} |")
print(f"| broker back → daemon connected (its back-off), s | {float(reconnected) - float(restart):.1f} |")
print(f"| history acknowledged / received by the subscriber | {sent} / {len(history)} |")
print(f"| history received, messages/s (first → last; past the first 100) | {rate(history):,.0f}; {after_window(history):,.0f} "
      f"({pauses(history)}) |")
print(f"| reference: mosquitto_pub -q 1 -M 100, the same documents, messages/s (first → last; past the first 100) "
      f"| {rate(reference):,.0f}; {after_window(reference):,.0f} ({len(reference)} messages, {pauses(reference)}) |")
print(f"| daemon CPU from the broker's restart to the buffer empty, s (of {float(delivered) - float(restart):.1f} s) | {cpu:.2f} |")
PY
