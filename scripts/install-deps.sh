#!/usr/bin/env bash
# Installs, from Debian 12's packages, everything unima-bridge needs to build, test and
# demo. Installs only what is missing; safe to run again.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
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
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "installing: ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
$sudo apt-get update -qq
# tshark's wireshark-common asks whether non-root users may capture; they need not, and
# the install must not stop to ask.
echo "wireshark-common wireshark-common/install-setuid boolean false" | $sudo debconf-set-selections
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
