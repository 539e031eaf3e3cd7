#!/usr/bin/env bash
# Builds the Debian package of unima-bridge for a Debian 12 box on this amd64 machine:
#   scripts/package.sh [amd64|arm64|armhf] [--test]
# (default: this machine's architecture). Installs what the architecture needs
# (scripts/install-package-deps.sh), cross-builds the daemon, the tool and the man pages
# with cmake/toolchains/<arch>.cmake in build-<arch>/ (or $BUILD_DIR), and writes
# packages/unima-bridge_<version>_<arch>.deb (or into $PACKAGE_DIR), its dependencies
# computed by dpkg-shlibdeps from the target's libraries. The package is then checked
# (tests/packaging/deb_contents.sh, as the amd64 package test does). With --test, the unit
# tests of the same tree run under qemu-user (all in one process), and so does the daemon
# on the demo config, read from this machine (tests/packaging/cross_smoke.sh). Says how
# long each step took, each step named with the architecture. scripts/test.sh runs
# `arm64 --test`; CTest runs either ARM architecture's with `-L arm64` or `-L armhf`.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/phases.sh
. scripts/generator.sh
host=$(dpkg --print-architecture)
arch=$host
run_tests=""
for argument in "$@"; do
  case $argument in
    amd64|arm64|armhf) arch=$argument ;;
    --test) run_tests=1 ;;
    *) echo "usage: scripts/package.sh [amd64|arm64|armhf] [--test]" >&2; exit 2 ;;
  esac
done
build_dir=${BUILD_DIR:-build-$arch}
package_dir=${PACKAGE_DIR:-packages}

phase "$arch install" scripts/install-package-deps.sh "$arch"
# CPack builds `preinstall` first, which would build every target of the tree (with --test the
# integration tests too): only what the package holds is built, above all else.
configure=(-DCMAKE_BUILD_TYPE=Release -DUNIMA_BUILD_BENCH=OFF -DCMAKE_SKIP_INSTALL_ALL_DEPENDENCY=ON -DUNIMA_BUILD_TESTS="$([ -n "$run_tests" ] && echo ON || echo OFF)")
if [ "$arch" != "$host" ]; then configure+=("-DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/$arch.cmake"); fi
phase "$arch configure" cmake -S . -B "$build_dir" "${configure[@]}" >/dev/null
targets=(--target unima-bridged --target unima-bridge --target man_pages)
if [ -n "$run_tests" ]; then targets+=(--target unit_tests); fi
phase "$arch build" cmake --build "$build_dir" -j "$(nproc)" "${targets[@]}"
# CPack runs dpkg-shlibdeps, which reads the target's libraries from dpkg's database (the
# multiarch packages); DEB_HOST_ARCH tells it which architecture's to take.
rm -rf "$build_dir/cpack"
phase "$arch package" env DEB_HOST_ARCH="$arch" cpack --config "$build_dir/CPackConfig.cmake" -G DEB -B "$build_dir/cpack" >/dev/null
mkdir -p "$package_dir"
deb=$(ls "$build_dir"/cpack/unima-bridge_*_"$arch".deb)
mv "$deb" "$package_dir/"
deb=$package_dir/$(basename "$deb")
phase "$arch check" env UNIMA_DEB="$deb" UNIMA_DEB_ARCH="$arch" UNIMA_SOURCE_DIR="$PWD" UNIMA_BUILD_DIR="$build_dir" \
  tests/packaging/deb_contents.sh
if [ -n "$run_tests" ]; then
  # A cross tree runs the unit tests as one process under qemu (tests/CMakeLists.txt), a
  # native one test by test.
  unit_label='^unit$'
  if [ "$arch" != "$host" ]; then unit_label='^one-process$'; fi
  phase "$arch unit tests" ctest --test-dir "$build_dir" -L "$unit_label" -j "$(nproc)" --output-on-failure --timeout 300
  phase "$arch smoke" tests/packaging/cross_smoke.sh "$build_dir" "$arch"
fi
echo "$deb"
