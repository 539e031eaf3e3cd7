#!/usr/bin/env bash
# Installs what is missing, builds a Release tree in build-release/ (or $BUILD_DIR) and
# runs the benchmark of docs/performance.md: unima-bridged beside the libmodbus reference.
# Extra arguments go to bench/run_bench.py (e.g. --rounds 9, --bridge-config FILE, --json F).
# Then Modbus/TCP Security against plain TCP (bench/tls.sh) and against stunnel4 in front of
# the libmodbus server (bench/tls_reference.sh), plain Modbus latency under a
# handshake flood (bench/tls_flood.sh), the cost of the HTTP server with its page open
# (bench/http.sh), MQTT's (bench/mqtt.sh), how soon a single change reaches MQTT and the
# page (bench/north_latency.py), MQTT history through a 60 s broker outage
# (bench/mqtt_outage.sh), Sparkplug B's latency, cost and births (bench/sparkplug.sh),
# Modbus latency while a peer guesses HTTP
# passwords (bench/auth_guess.sh), the gateway's use of an RTU line (bench/gateway;
# MBUSD=/path/to/mbusd runs mbusd beside it) and of two lines at once (its --lines), how
# fast the monitor log becomes a pcap (bench/pcap.sh), what a deadband saves the north
# (bench/deadband.py), every feature at once beside the minimal config with the page's and
# Sparkplug's shares (bench/all_features.py), what a change of config from afar costs the
# Modbus clients of a port it keeps (bench/remote_config.py), and this tree's daemon in
# paired rounds at 1, 8 and 64 connections against its parent commit's and against
# bf83827's, the fixed older reference of the plain path (bench/against_commit.sh;
# SKIP_COMMITS=1 skips both).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build-release} BUILD_TYPE=Release scripts/build.sh
python3 bench/run_bench.py --build-dir "${BUILD_DIR:-build-release}" "$@"
bench/tls.sh "${BUILD_DIR:-build-release}"
bench/tls_reference.sh "${BUILD_DIR:-build-release}"
bench/tls_flood.sh "${BUILD_DIR:-build-release}"
bench/http.sh "${BUILD_DIR:-build-release}"
bench/mqtt.sh "${BUILD_DIR:-build-release}"
bench/mqtt_outage.sh "${BUILD_DIR:-build-release}"
python3 bench/north_latency.py --bridged "${BUILD_DIR:-build-release}/bin/unima-bridged" --rounds 3
bench/sparkplug.sh "${BUILD_DIR:-build-release}"
bench/auth_guess.sh "${BUILD_DIR:-build-release}"
gateway_args=(--load "${BUILD_DIR:-build-release}/bench/unima-bench-load")
if [[ -n "${MBUSD:-}" ]]; then gateway_args+=(--mbusd "$MBUSD"); fi
"${BUILD_DIR:-build-release}/bench/gateway/gateway_bench" "${gateway_args[@]}"
"${BUILD_DIR:-build-release}/bench/gateway/gateway_bench" --lines --load "${BUILD_DIR:-build-release}/bench/unima-bench-load"
bench/pcap.sh "${BUILD_DIR:-build-release}"
python3 bench/deadband.py --bridged "${BUILD_DIR:-build-release}/bin/unima-bridged" --load "${BUILD_DIR:-build-release}/bench/unima-bench-load"
python3 bench/all_features.py --build-dir "${BUILD_DIR:-build-release}"
python3 bench/remote_config.py --build-dir "${BUILD_DIR:-build-release}"
if [[ -z "${SKIP_COMMITS:-}" ]]; then
  bench/against_commit.sh HEAD~1 "${BUILD_DIR:-build-release}"
  bench/against_commit.sh bf83827 "${BUILD_DIR:-build-release}"
fi
