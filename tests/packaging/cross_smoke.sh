#!/usr/bin/env bash
# The daemon of a build for another architecture, run under qemu-user on the demo config
# (scripts/package.sh ARCH --test): this machine's mbpoll and pymodbus read D1 over Modbus
# TCP, curl reads /metrics, and SIGTERM stops it cleanly.
# Usage: tests/packaging/cross_smoke.sh BUILD_DIR ARCH
. "$(dirname "$0")/lib.sh"
build=$1
arch=$2
[ -f "$build/CMakeCache.txt" ] || fail "$build is not a configured build tree"
# The emulator the tree's unit tests run under (cmake/toolchains/debian-cross.cmake), a
# CMake list; none in a native build.
IFS=';' read -r -a emulator <<<"$(sed -n 's/^CMAKE_CROSSCOMPILING_EMULATOR:[A-Z]*=//p' "$build/CMakeCache.txt")"
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
modbus_port=$(free_port)
http_port=$(free_port)
# The demo config as shipped, on free ports, its files in the scratch directory (the state
# file lands beside the config).
sed -e "s/port: 5020/port: $modbus_port/; s/port: 8080/port: $http_port/" \
    -e "s|/tmp/unima-bridge-demo|$scratch|g" "$source_dir/config/examples/demo.yaml" >"$scratch/demo.yaml"
"${emulator[@]}" "$build/bin/unima-bridged" --config "$scratch/demo.yaml" >"$scratch/daemon.log" 2>&1 &
daemon=$!
# When a check fails the daemon may be stuck where SIGTERM is not yet handled: it must
# not outlive the test.
kill_daemon() { [ -z "$daemon" ] || kill -KILL "$daemon" 2>/dev/null || true; }
trap 'kill_daemon; rm -rf "$scratch"' EXIT
# Emulated, the daemon starts in seconds rather than milliseconds: up to 60 s.
for _ in $(seq 600); do
  if curl -sf "http://127.0.0.1:$http_port/metrics" >"$scratch/metrics" 2>/dev/null; then break; fi
  kill -0 "$daemon" 2>/dev/null || { cat "$scratch/daemon.log" >&2; fail "the $arch daemon exited"; }
  sleep 0.1
done
grep -q '^unima_' "$scratch/metrics" || { cat "$scratch/daemon.log" >&2; fail "no unima_ metric in /metrics"; }

# D1 (the CHP unit) from 0x1100 as the demo's comment reads it; the simulation fills it
# within its first period.
mbpoll -m tcp -p "$modbus_port" -a 1 -t 3 -r 4353 -c 10 -1 127.0.0.1 >"$scratch/mbpoll" 2>&1 ||
  { cat "$scratch/mbpoll" "$scratch/daemon.log" >&2; fail "mbpoll could not read D1"; }
[ "$(grep -c '^\[' "$scratch/mbpoll")" -eq 10 ] || { cat "$scratch/mbpoll" >&2; fail "mbpoll read not 10 registers"; }
/usr/bin/python3 - "$modbus_port" <<'PY' || fail "pymodbus could not read D1"
import sys
from pymodbus.client import ModbusTcpClient
client = ModbusTcpClient("127.0.0.1", port=int(sys.argv[1]), timeout=10)
assert client.connect(), "no connection"
answer = client.read_input_registers(0x1100, 10, slave=1)
assert not answer.isError(), answer
assert len(answer.registers) == 10, answer.registers
client.close()
PY

kill -TERM "$daemon"
for _ in $(seq 300); do kill -0 "$daemon" 2>/dev/null || break; sleep 0.1; done
kill -0 "$daemon" 2>/dev/null && fail "the $arch daemon did not stop within 30 s of SIGTERM"
stopped=$daemon
daemon=""
wait "$stopped" || { status=$?; cat "$scratch/daemon.log" >&2; fail "the $arch daemon exited with status $status on SIGTERM"; }
echo "the $arch daemon served D1 to mbpoll and pymodbus and /metrics, and stopped on SIGTERM"
