#!/usr/bin/env bash
# Installs what is missing, builds, and runs the daemon on the demo config: a simulated
# UnimaBUS plant, Modbus TCP on 127.0.0.1:5020. Stop it with Ctrl-C.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
exec "${BUILD_DIR:-build}"/bin/unima-bridged --config config/examples/demo.yaml
