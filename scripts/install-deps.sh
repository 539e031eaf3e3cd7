#!/usr/bin/env bash
# Installs, from Debian 12's packages, everything unima-bridge needs to build, test and
# demo. Installs only what is missing; safe to run again.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libmodbus-dev libboost-dev libyaml-cpp-dev libspdlog-dev libfmt-dev libsystemd-dev
  nlohmann-json3-dev googletest libgtest-dev
  # Modbus/TCP Security: OpenSSL for the daemon; the command line makes the tests' certificates
  libssl-dev openssl
  # /metrics is checked by Prometheus' own promtool; the front page in headless Chromium over WebDriver
  prometheus chromium chromium-driver
  # MQTT: the client library; the broker and its command-line clients for the tests
  libmosquitto-dev mosquitto mosquitto-clients
  # MQTT 5 request/response in the tests: paho-mqtt as the fleet's application (tests/integration/mqtt)
  python3-paho-mqtt
  # Home Assistant's command templates rendered by Jinja itself (tests/integration/mqtt_discovery_test)
  python3-jinja2
  mbpoll socat
  # HTTP clients of the tests: PUT /api/config (tests/integration/http_remote_config_test), the ARM smoke's /metrics
  curl
  # the monitor's pcap read back by Wireshark's own dissectors (SPEC §20)
  tshark
  # packaging tests: systemd-analyze, systemd-sysusers/-tmpfiles, man, dpkg-shlibdeps, shellcheck
  systemd man-db groff-base dpkg-dev shellcheck
  # benchmarks: the runner, exact system-call and instruction counts
  python3 strace valgrind
  # the TLS benchmark's reference: stunnel in front of the libmodbus server (bench/tls.sh)
  stunnel4
  # fuzzing (fuzz/, docs/fuzzing.md): clang 14 and its libFuzzer, ASan and UBSan runtimes
  clang libclang-rt-dev
  # Eclipse Tahu's Sparkplug codec runs in Node.js (tests/support/tahu, below)
  nodejs
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Debian's npm is a package of its own; NodeSource's nodejs carries one (and conflicts with it).
command -v npm >/dev/null || missing+=(npm)
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  # tshark's wireshark-common asks whether non-root users may capture; they need not, and
  # the install must not stop to ask.
  echo "wireshark-common wireshark-common/install-setuid boolean false" | $sudo debconf-set-selections
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Eclipse Tahu's Sparkplug B codec (npm `sparkplug-payload`), an independent decoder of what
# the daemon publishes (tests/integration/sparkplug_tahu_test.cpp). It is not a Debian
# package: npm installs the versions tests/support/tahu/package-lock.json pins, with their
# checksums, once per machine, outside the source tree (a fresh clone finds it there).
tahu_dir=/usr/local/lib/unima-bridge-tests/tahu
tahu_source="$(dirname "$0")/../tests/support/tahu"
if ! cmp -s "$tahu_source/package-lock.json" "$tahu_dir/package-lock.json" ||
   [ ! -f "$tahu_dir/node_modules/sparkplug-payload/package.json" ]; then
  echo "installing Eclipse Tahu's sparkplug-payload into $tahu_dir"
  $sudo mkdir -p "$tahu_dir"
  $sudo cp "$tahu_source/package.json" "$tahu_source/package-lock.json" "$tahu_dir/"
  # --ignore-scripts: protobufjs' postinstall only prints; nothing of the package runs as root
  (cd "$tahu_dir" && $sudo npm ci --no-audit --no-fund --ignore-scripts --loglevel=error)
fi
