#!/usr/bin/env bash
# Issue 29 row 3, measured: plain Modbus/TCP latency while one host floods the Modbus/TCP
# Security port with handshakes (docs/performance.md). One daemon serves both ports; in
# paired rounds whose order alternates, unima-bench-load measures FC4 × 64 on the plain
# port (8 connections) alone, and again while unima-bench-tls-load --mode flood replays one
# ClientHello from 127.0.0.2 on new connections (8 at once, at most FLOOD_RATE a second,
# default 2000 — more than the daemon could answer without a limit — for the round's
# seconds and at most FLOOD_RATE × seconds connections). Reports p99 idle and under the
# flood and their ratio (median of the rounds; the target is within 2×), and what the
# flood got: connections, the ones the daemon answered with its first flight. Then the
# flood alone, and the daemon's CPU time meanwhile (utime + stime from /proc, as a share
# of one core): the loop's cost of the flood, which other work on the machine does not
# change the way it changes a p99.
# FLOOD_BRIDGED=path measures another build of the daemon (the filed one, say) with this
# build's clients.
# Usage: bench/tls_flood.sh [BUILD_DIR] [ROUNDS] [SECONDS]   (default build-release 5 3)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/paired_rounds.sh
bridged=${FLOOD_BRIDGED:-$bridged}
tls_load=$(find "$build" -name unima-bench-tls-load -type f | head -1)
rate=${FLOOD_RATE:-2000}
tests/integration/tls/make_certificates.sh "$work/certs"
certs=$work/certs

plain=$(free_port); tls=$(free_port)
{
  echo "unimabus: { transport: sim }"
  echo "modbus:"
  echo "  tcp: { listen: 127.0.0.1, port: $plain, max_clients: 256 }"
  echo "  tls: { listen: 127.0.0.1, port: $tls, max_clients: 256, certificate: $certs/server.pem,"
  echo "         key: $certs/server.key, ca: $certs/ca.pem, roles: { operator: { write: [W] } } }"
  echo "banks: { D1: 0x1100 }"
  echo "devices: { D1: { type: unigen-chp, address: 5 } }"
  echo "log: { level: error }"
  echo "status: { socket: $work/bridge.sock }"
  echo "state: { file: none }"
} > "$work/bridge.yaml"
"$bridged" --config "$work/bridge.yaml" > "$work/bridge.log" 2>&1 &
pids+=($!)
daemon_pid=$!
started=
for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/"$plain") 2>/dev/null && { started=1; break; }; sleep 0.05; done
[ -n "$started" ] || { echo "the daemon did not start:"; cat "$work/bridge.log"; exit 1; }

measure() {  # prints the plain port's p99 in µs
  "$load" --port "$plain" --connections 8 --function 4 --address 4352 --quantity 64 --duration "$seconds" \
    --warmup 0.2 --json | field p99_us
}
flood() {  # [port] runs for the round (and its warm-up), writes its JSON to $work/flood.json
  local span attempts target=${1:-$tls}
  span=$(python3 -c "print($seconds + 0.4)")
  attempts=$(python3 -c "print(int($rate * $span))")
  "$tls_load" --port "$target" --mode flood --source 127.0.0.2 --connections 8 --rate "$rate" \
    --attempts "$attempts" --duration "$span" > "$work/flood.json"
}

cpu_seconds() { awk -v hz="$(getconf CLK_TCK)" '{ print ($14 + $15) / hz }' "/proc/$daemon_pid/stat"; }

# The control: the same flood at a port nothing listens on (each connection refused by the
# kernel), which costs the daemon nothing: what the flooding process and the kernel take
# from two shared cores alone.
closed=$(free_port)
idle=(); flooded=(); ratio=(); per_s=(); answered=(); busy=(); control=(); control_ratio=()
for round in $(seq "$rounds"); do
  order=(idle flood control)
  [ $((round % 2)) = 0 ] && order=(control flood idle)
  for what in "${order[@]}"; do
    if [ "$what" = idle ]; then
      i=$(measure)
    elif [ "$what" = control ]; then
      flood "$closed" & flooder=$!
      sleep 0.1
      c=$(measure)
      wait "$flooder" || true
    else
      flood & flooder=$!
      sleep 0.1  # the flood is on before the first request is timed
      f=$(measure)
      wait "$flooder"
      per_s+=("$(field per_s < "$work/flood.json")")
      answered+=("$(python3 -c "import json; d = json.load(open('$work/flood.json')); print(d['answered'] / max(d['attempts'], 1))")")
    fi
  done
  idle+=("$i"); flooded+=("$f"); ratio+=("$(python3 -c "print($f / $i)")")
  control+=("$c"); control_ratio+=("$(python3 -c "print($c / $i)")")
done
for _ in $(seq "$rounds"); do
  before=$(cpu_seconds); start=$(date +%s.%N)
  flood
  after=$(cpu_seconds); end=$(date +%s.%N)
  busy+=("$(python3 -c "print(($after - $before) / ($end - $start))")")
done

echo "| measure (median of $rounds paired rounds) | value |"
echo "|---|---|"
echo "| plain FC4 × 64, 8 connections, p99 µs, idle | $(median "${idle[@]}") |"
echo "| the same while 127.0.0.2 floods the TLS port with one replayed ClientHello, p99 µs | $(median "${flooded[@]}") |"
echo "| ratio flood / idle (target ≤ 2) | $(median "${ratio[@]}") |"
echo "| control: the same flood at a closed port (the daemon does nothing), p99 µs | $(median "${control[@]}") |"
echo "| ratio control / idle: what the flooding process alone costs the machine | $(median "${control_ratio[@]}") |"
echo "| the flood's connections a second | $(median "${per_s[@]}") |"
echo "| share of them the daemon answered with its first flight (a handshake's cryptography) | $(median "${answered[@]}") |"
echo "| the daemon's CPU during the flood alone, share of one core | $(median "${busy[@]}") |"
