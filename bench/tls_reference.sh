#!/usr/bin/env bash
# Modbus/TCP Security against what a site would otherwise deploy (issue 29,
# docs/performance.md): stunnel4 terminating TLS (mutual authentication, the same
# certificates) in front of the libmodbus reference server (unima-bench-libmodbus-server),
# against the daemon's own TLS port. One client (unima-bench-tls-load, OpenSSL's records)
# drives both in paired rounds whose order alternates: FC4 × 64 at 8 and 64 connections,
# TLS 1.3 and TLS 1.2, requests/s and p99; the ratio is the daemon's over the reference's
# (above 1: the daemon is ahead). Full handshakes/s of both as well. The connections come
# from as many addresses of 127/8 as there are (--hosts), since the daemon limits
# handshakes per host and stunnel does not.
# Usage: bench/tls_reference.sh [BUILD_DIR] [ROUNDS] [SECONDS]   (default build-release 5 3)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/paired_rounds.sh
tls_load=$(find "$build" -name unima-bench-tls-load -type f | head -1)
reference=$(find "$build" -name unima-bench-libmodbus-server -type f | head -1)
stunnel=$(command -v stunnel4 || command -v stunnel || true)
if [ -z "$stunnel" ]; then echo "stunnel4 is not installed (scripts/install-deps.sh installs it)"; exit 1; fi
tests/integration/tls/make_certificates.sh "$work/certs" > /dev/null
certs=$work/certs

wait_for_port() {  # port, log file
  for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/"$1") 2>/dev/null && return; sleep 0.05; done
  echo "nothing listens on $1:"; cat "$2"; exit 1
}

daemon_tls=$(free_port); daemon_plain=$(free_port)
cat > "$work/bridge.yaml" <<EOF
unimabus: { transport: sim }
modbus:
  tcp: { listen: 127.0.0.1, port: $daemon_plain, max_clients: 256 }
  tls: { listen: 127.0.0.1, port: $daemon_tls, max_clients: 256, certificate: $certs/server.pem,
         key: $certs/server.key, ca: $certs/ca.pem, roles: { operator: { write: [W] } } }
banks: { D1: 0x1100 }
devices: { D1: { type: unigen-chp, address: 5 } }
log: { level: warn }
status: { socket: $work/bridge.sock }
state: { file: none }
EOF
"$bridged" --config "$work/bridge.yaml" > "$work/bridge.log" 2>&1 &
pids+=($!)
wait_for_port "$daemon_tls" "$work/bridge.log"

# The reference: libmodbus's select loop, and stunnel as a site would configure it for
# Modbus/TCP Security (client certificates required and checked against the same CA).
reference_plain=$(free_port); reference_tls=$(free_port)
"$reference" --port "$reference_plain" --address 0x1100 --count 64 > "$work/reference.log" 2>&1 &
pids+=($!)
wait_for_port "$reference_plain" "$work/reference.log"
cat > "$work/stunnel.conf" <<EOF
foreground = yes
pid =
output = $work/stunnel.log
debug = 3
[modbus-security]
accept = 127.0.0.1:$reference_tls
connect = 127.0.0.1:$reference_plain
cert = $certs/server.pem
key = $certs/server.key
CAfile = $certs/ca.pem
requireCert = yes
verifyChain = yes
sslVersionMin = TLSv1.2
socket = r:TCP_NODELAY=1
socket = l:TCP_NODELAY=1
EOF
"$stunnel" "$work/stunnel.conf" > "$work/stunnel.out" 2>&1 &
pids+=($!)
wait_for_port "$reference_tls" "$work/stunnel.out"

tls_run() {  # port, connections, TLS version
  "$tls_load" --port "$1" --tls "$certs/ca.pem" "$certs/operator.pem" "$certs/operator.key" --tls-version "$3" \
    --hosts "$2" --connections "$2" --duration "$seconds"
}
handshakes() {  # port
  "$tls_load" --port "$1" --tls "$certs/ca.pem" "$certs/operator.pem" "$certs/operator.key" \
    --mode handshakes --hosts 4096 --connections 8 --duration "$seconds" | field handshakes_per_s
}

declare -A series
for version in 1.3 1.2; do
  for connections in 8 64; do
    for round in $(seq "$rounds"); do
      order=(daemon reference)
      [ $((round % 2)) = 0 ] && order=(reference daemon)
      declare -A rps=()
      for server in "${order[@]}"; do
        port=$daemon_tls
        [ "$server" = reference ] && port=$reference_tls
        json=$(tls_run "$port" "$connections" "$version")
        rps[$server]=$(echo "$json" | field rps)
        series[rps,$server,$version,$connections]+=" ${rps[$server]}"
        series[p99,$server,$version,$connections]+=" $(echo "$json" | field p99_us)"
      done
      series[ratio,$version,$connections]+=" $(python3 -c "print(${rps[daemon]} / ${rps[reference]})")"
    done
  done
done
for round in $(seq "$rounds"); do
  if [ $((round % 2)) = 1 ]; then d=$(handshakes "$daemon_tls"); r=$(handshakes "$reference_tls")
  else r=$(handshakes "$reference_tls"); d=$(handshakes "$daemon_tls"); fi
  series[hs,daemon]+=" $d"; series[hs,reference]+=" $r"
  series[hs,ratio]+=" $(python3 -c "print($d / $r)")"
done

m() {  # shellcheck disable=SC2086  # the series are space-separated numbers
  median ${series[$1]}
}
echo "| measure (median of $rounds paired rounds) | the daemon's TLS port | stunnel4 + libmodbus | daemon / reference |"
echo "|---|---|---|---|"
for version in 1.3 1.2; do
  for connections in 8 64; do
    echo "| TLS $version, FC4 × 64, $connections connections, requests/s | $(m "rps,daemon,$version,$connections") | $(m "rps,reference,$version,$connections") | $(m "ratio,$version,$connections") |"
    echo "| TLS $version, FC4 × 64, $connections connections, p99 µs | $(m "p99,daemon,$version,$connections") | $(m "p99,reference,$version,$connections") | |"
  done
done
echo "| full handshakes/s (TLS 1.3, ECDSA P-256, 8 at once) | $(m hs,daemon) | $(m hs,reference) | $(m hs,ratio) |"
