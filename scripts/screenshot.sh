#!/usr/bin/env bash
# The README's picture of the front page (docs/images/front-page.png), taken again from the
# demo config: the built daemon on free ports, a master's write to W+0x00 for capture
# indicator 1, headless Chromium at desktop width (tests/integration/browser/
# page_in_chromium.py), one window high so that the PNG stays under 200 KiB.
# Needs a build (scripts/build.sh), chromium, chromium-driver and mbpoll.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${BUILD_DIR:-build}"
out="${1:-docs/images/front-page.png}"
work="$(mktemp -d)"
daemon=""
cleanup() {
  if [ -n "$daemon" ]; then kill "$daemon" 2>/dev/null || true; wait "$daemon" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT

free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
modbus_port="$(free_port)"
http_port="$(free_port)"
sed -e "s/port: 5020/port: $modbus_port/" -e "s/port: 8080/port: $http_port/" \
    -e "s|/tmp/unima-bridge-demo|$work|" config/examples/demo.yaml >"$work/demo.yaml"
"$build"/bin/unima-bridged --config "$work/demo.yaml" >"$work/daemon.log" 2>&1 &
daemon=$!
for _ in $(seq 100); do
  mbpoll -m tcp -p "$modbus_port" -t 4:hex -r 12289 -1 127.0.0.1 0x1234 >/dev/null 2>&1 && break
  sleep 0.1
done
tests/integration/browser/page_in_chromium.py --url "http://127.0.0.1:$http_port/" --online D1 --online D2 \
  --indicator 1=write --screenshot "$work/page.png" --window 1200,1100 --timeout 30 >/dev/null
cp "$work/page.png" "$out"
echo "$out: $(stat -c %s "$out") bytes"
