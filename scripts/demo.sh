#!/usr/bin/env bash
# Installs what is missing, builds the daemon and the operator's tool (nothing else: no
# tests, no benchmarks), and runs the daemon on the demo config: a simulated UnimaBUS
# plant, Modbus TCP on 127.0.0.1:5020. Stop it with Ctrl-C. Says how long each step took.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/phases.sh
phase install scripts/install-deps.sh
# What the demo runs: the daemon, and the tool the README has the reader try beside it.
BUILD_TARGETS="unima-bridged unima-bridge" scripts/build.sh
phase_summary
echo "== starting the daemon; mbpoll -m tcp -p 5020 -t 3 -r 4353 -c 10 127.0.0.1 reads D1" >&2
exec "${BUILD_DIR:-build}"/bin/unima-bridged --config config/examples/demo.yaml
