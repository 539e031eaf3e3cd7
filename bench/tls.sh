#!/usr/bin/env bash
# Modbus/TCP Security against plain Modbus TCP (issue 18, docs/performance.md), one daemon
# serving both, measured by one client (unima-bench-tls-load) in paired rounds whose order
# alternates: FC4 × 64 at 8 and 64 connections, TLS as a ratio of plain (medians); full
# ECDSA P-256 handshakes per second; and plain TCP of a daemon with TLS configured but
# idle against one without TLS (unima-bench-load, 64 connections). Beside requests/s, the
# daemon's own CPU time in each round (utime + stime from /proc): requests per CPU-second
# of the daemon, which the client sharing the machine's cores does not change. TLS 1.3 and
# TLS 1.2 are measured alike, every record OpenSSL's on both sides; the client's own CPU
# time per request is printed too (on 2 shared cores it bounds the figure). The clients
# come from many addresses of 127/8 (--hosts), as the daemon limits handshakes per host
# (docs/security.md); a flood from one host is bench/tls_flood.sh's.
# Usage: bench/tls.sh [BUILD_DIR] [ROUNDS] [SECONDS]   (default build-release 5 3)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/paired_rounds.sh
tls_load=$(find "$build" -name unima-bench-tls-load -type f | head -1)
tests/integration/tls/make_certificates.sh "$work/certs"
certs=$work/certs

start_daemon() {  # name, plain port, tls port (0: none)
  local name=$1 plain=$2 tls=$3
  {
    echo "unimabus: { transport: sim }"
    echo "modbus:"
    echo "  tcp: { listen: 127.0.0.1, port: $plain, max_clients: 256 }"
    if [ "$tls" != 0 ]; then
      echo "  tls: { listen: 127.0.0.1, port: $tls, max_clients: 256, certificate: $certs/server.pem,"
      echo "         key: $certs/server.key, ca: $certs/ca.pem, roles: { operator: { write: [W] } } }"
    fi
    echo "banks: { D1: 0x1100 }"
    echo "devices: { D1: { type: unigen-chp, address: 5 } }"
    echo "log: { level: warn }"
    echo "status: { socket: $work/$name.sock }"
    echo "state: { file: none }"
  } > "$work/$name.yaml"
  "$bridged" --config "$work/$name.yaml" > "$work/$name.log" 2>&1 &
  pids+=($!)
  for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/"$plain") 2>/dev/null && return; sleep 0.05; done
  echo "the daemon did not start:"; cat "$work/$name.log"; exit 1
}

plain=$(free_port); tls=$(free_port); bare=$(free_port)
start_daemon both "$plain" "$tls"
both_pid=${pids[0]}
start_daemon bare "$bare" 0

plain_run() { "$tls_load" --port "$plain" --hosts "$1" --connections "$1" --duration "$seconds"; }
tls_run() {  # connections, version (1.3 or 1.2)
  "$tls_load" --port "$tls" --tls "$certs/ca.pem" "$certs/operator.pem" "$certs/operator.key" --tls-version "$2" \
    --hosts "$1" --connections "$1" --duration "$seconds"
}
load_rps() { "$load" --port "$1" --connections 64 --function 4 --address 4352 --quantity 64 --duration "$seconds" --warmup 0.5 --json | field rps; }

cpu_seconds() { awk -v hz="$(getconf CLK_TCK)" '{ print ($14 + $15) / hz }' "/proc/$both_pid/stat"; }
# Runs one measurement ($@ prints the client's JSON) and prints "requests/s
# requests-per-daemon-CPU-second client-CPU-µs-per-request".
with_daemon_cpu() {
  local before json rps after
  before=$(cpu_seconds); json=$("$@"); after=$(cpu_seconds)
  rps=$(echo "$json" | field rps)
  echo "$rps $(python3 -c "print(round($rps * $seconds / max($after - $before, 0.01)))") $(echo "$json" | field client_cpu_us)"
}

# Each round measures plain TCP, TLS 1.3 and TLS 1.2, in an order that alternates.
# Keys: <measure>,<connections>,<client> with client plain, 1.3 or 1.2.
declare -A results
for connections in 8 64; do
  declare -A series=()
  for round in $(seq "$rounds"); do
    clients=(plain 1.3 1.2)
    [ $((round % 2)) = 0 ] && clients=(1.2 1.3 plain)
    declare -A rps=() cpu=()
    for client in "${clients[@]}"; do
      if [ "$client" = plain ]; then read -r r c k < <(with_daemon_cpu plain_run "$connections")
      else read -r r c k < <(with_daemon_cpu tls_run "$connections" "$client"); fi
      rps[$client]=$r; cpu[$client]=$c
      series[rps,$client]+=" $r"; series[cpu,$client]+=" $c"; series[client,$client]+=" $k"
    done
    for client in 1.3 1.2; do
      series[ratio,$client]+=" $(python3 -c "print(${rps[$client]} / ${rps[plain]})")"
      series[cpu_ratio,$client]+=" $(python3 -c "print(${cpu[$client]} / ${cpu[plain]})")"
    done
  done
  for key in "${!series[@]}"; do
    # shellcheck disable=SC2086  # the series are space-separated numbers
    results[$key,$connections]=$(median ${series[$key]})
  done
done
handshakes_per_s() {
  "$tls_load" --port "$tls" --tls "$certs/ca.pem" "$certs/operator.pem" "$certs/operator.key" \
    --mode handshakes --hosts 4096 --connections 8 --duration "$seconds" | field handshakes_per_s
}
# Handshakes per second, and per CPU-second of the daemon.
handshakes_with_daemon_cpu() {
  local before n after
  before=$(cpu_seconds); n=$(handshakes_per_s); after=$(cpu_seconds)
  echo "$n $(python3 -c "print(round($n * $seconds / max($after - $before, 0.01)))")"
}
h=(); ch=()
for _ in $(seq "$rounds"); do
  read -r a ca < <(handshakes_with_daemon_cpu)
  h+=("$a"); ch+=("$ca")
done
idle=()
for round in $(seq "$rounds"); do
  if [ $((round % 2)) = 1 ]; then a=$(load_rps "$plain"); b=$(load_rps "$bare")
  else b=$(load_rps "$bare"); a=$(load_rps "$plain"); fi
  idle+=("$(python3 -c "print($a / $b)")")
done

echo "| measure | plain TCP | TLS | ratio (median of $rounds paired rounds) |"
echo "|---|---|---|---|"
row() {  # label, measure, connections, client (the ratio's measure is ratio or cpu_ratio)
  local ratio=ratio
  [ "$2" = cpu ] && ratio=cpu_ratio
  echo "| $1 | ${results[$2,plain,$3]} | ${results[$2,$4,$3]} | ${results[$ratio,$4,$3]} |"
}
for connections in 8 64; do
  row "FC4 × 64, $connections connections, requests/s, TLS 1.3" rps "$connections" 1.3
  row "FC4 × 64, $connections connections, requests/s, TLS 1.2" rps "$connections" 1.2
done
for connections in 8 64; do
  row "FC4 × 64, $connections connections, requests per CPU-second of the daemon, TLS 1.3" cpu "$connections" 1.3
  row "FC4 × 64, $connections connections, requests per CPU-second of the daemon, TLS 1.2" cpu "$connections" 1.2
done
for connections in 8 64; do
  echo "| FC4 × 64, $connections connections, the client's CPU µs per request: plain \| TLS 1.3 \| TLS 1.2 | ${results[client,plain,$connections]} | ${results[client,1.3,$connections]} | ${results[client,1.2,$connections]} |"
done
echo "| full handshakes/s (ECDSA P-256, TLS 1.3, 8 at once) | | $(median "${h[@]}") | |"
echo "| full handshakes per CPU-second of the daemon | | $(median "${ch[@]}") | |"
echo "| plain FC4 × 64 at 64 connections, TLS configured and idle vs no TLS (unima-bench-load) | | | $(median "${idle[@]}") |"
