#!/usr/bin/env bash
# Installs, from Debian 12's packages, what scripts/package.sh needs to build and test the
# package for ARCH (amd64, arm64 or armhf) on an amd64 machine: the host's build tools, and
# for another architecture its cross compiler, its libraries as multiarch packages
# (`libmodbus-dev:arm64` ...) and qemu-user to run its programs. Installs only what is
# missing; safe to run again.
set -euo pipefail
arch=${1:?usage: scripts/install-package-deps.sh amd64|arm64|armhf}
host=$(dpkg --print-architecture)
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi

# What builds and checks the package on the host, whatever its architecture.
host_packages=(build-essential cmake ninja-build pkg-config dpkg-dev file nlohmann-json3-dev libyaml-cpp-dev
               mbpoll curl
               # pymodbus from Debian, with the serial module it imports (a Recommends); run by /usr/bin/python3
               python3-pymodbus python3-serial-asyncio)
# The libraries the tree links, for the target. libyaml-cpp-dev is not Multi-Arch: same in
# Debian 12 (the target's would remove the host's), so the target gets only the runtime
# library and the build uses the host's headers of the same version
# (cmake/cross/yaml-cpp/yaml-cpp-config.cmake).
target_libraries=(libmodbus-dev libboost-dev libspdlog-dev libfmt-dev libssl-dev libmosquitto-dev
                  libsystemd-dev libgtest-dev)
wanted=("${host_packages[@]}")
if [ "$arch" = "$host" ]; then
  wanted+=("${target_libraries[@]}")
else
  case $arch in
    arm64|armhf) ;;
    *) echo "unknown architecture $arch (amd64, arm64 or armhf)" >&2; exit 2 ;;
  esac
  # libc6:<arch> (which the libraries pull in anyway) is the loader and C library qemu runs
  # the target's programs with (cmake/toolchains/debian-cross.cmake).
  wanted+=("crossbuild-essential-$arch" qemu-user-static "libc6:$arch" "libyaml-cpp0.7:$arch" "pkgconf:$arch")
  for library in "${target_libraries[@]}"; do wanted+=("$library:$arch"); done
fi

missing=()
for p in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  if [ "$arch" != "$host" ] && ! dpkg --print-foreign-architectures | grep -qx "$arch"; then
    $sudo dpkg --add-architecture "$arch"
  fi
  # A target library must have exactly its host twin's version. An index that fails to
  # download (a mirror mid-sync) would leave apt with one side older than the other, so
  # any failed index stops here instead of installing skewed versions.
  if ! $sudo apt-get update -qq --error-on=any; then
    echo "apt-get update could not read every index (a mirror mid-sync?): nothing was installed;" \
         "run scripts/package.sh $arch again later" >&2
    exit 1
  fi
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if [ "$arch" != "$host" ]; then
  # The host's yaml-cpp headers and the target's library must be one version.
  headers=$(dpkg-query -W -f='${Version}' libyaml-cpp-dev)
  library=$(dpkg-query -W -f='${Version}' "libyaml-cpp0.7:$arch")
  if [ "$headers" != "$library" ]; then
    echo "libyaml-cpp-dev $headers (headers) and libyaml-cpp0.7:$arch $library differ; run apt-get upgrade" >&2
    exit 1
  fi
fi
