#!/usr/bin/env bash
# What the .deb holds (dpkg-deb -c) and declares (dpkg-deb -I), that its programs are built
# for its architecture, and that Debian 12's apt can satisfy its dependencies here.
# scripts/package.sh runs it on a package of another architecture too: UNIMA_DEB names the
# package and UNIMA_DEB_ARCH its architecture (default: this machine's).
. "$(dirname "$0")/lib.sh"
deb=${UNIMA_DEB:-$(ls "$UNIMA_DEB_DIR"/unima-bridge_*.deb)}
arch=${UNIMA_DEB_ARCH:-$(dpkg --print-architecture)}
version=$(sed -n 's/^CPACK_PACKAGE_VERSION "\(.*\)"$/\1/p; s/^set(CPACK_PACKAGE_VERSION "\(.*\)")$/\1/p' \
  "$UNIMA_BUILD_DIR/CPackConfig.cmake" | head -n1)
[ "$(basename "$deb")" = "unima-bridge_${version}_${arch}.deb" ] || fail "file name $(basename "$deb")"

dpkg-deb -c "$deb" | awk '{ print $1, $2, $6 }' >"$scratch/contents"
expect_entry() {  # mode, path
  grep -qxF -- "$1 root/root ./$2" "$scratch/contents" || { cat "$scratch/contents" >&2; fail "no $1 ./$2 owned by root"; }
}
expect_entry -rwxr-xr-x usr/sbin/unima-bridged
expect_entry -rwxr-xr-x usr/bin/unima-bridge
expect_entry -rw-r--r-- usr/lib/systemd/system/unima-bridge.service
expect_entry -rw-r--r-- usr/lib/sysusers.d/unima-bridge.conf
expect_entry -rw-r--r-- usr/lib/tmpfiles.d/unima-bridge.conf
expect_entry -rw-r--r-- etc/unima-bridge/bridge.yaml
expect_entry -rw-r--r-- usr/share/man/man8/unima-bridged.8.gz
expect_entry -rw-r--r-- usr/share/man/man1/unima-bridge.1.gz
# Every document of docs/, listed from the source tree so a new one cannot be left out.
sources=("$UNIMA_SOURCE_DIR"/docs/*.md)
[ "${#sources[@]}" -ge 12 ] || fail "expected the 12 documents of docs/ at least, found ${#sources[@]}"
docs=(copyright README.md docs/images/front-page.png examples/bridge.yaml examples/chp-site.yaml)
for doc in "${sources[@]}"; do docs+=("$(basename "$doc")"); done
for doc in "${docs[@]}"; do
  expect_entry -rw-r--r-- "usr/share/doc/unima-bridge/$doc"
done
if grep -q '\./usr/local\|\./tmp\|_CPack' "$scratch/contents"; then fail "stray paths in the package"; fi
# Debian policy 12.5: the copyright file in the machine-readable format, with a license.
dpkg-deb --fsys-tarfile "$deb" | tar -xO ./usr/share/doc/unima-bridge/copyright >"$scratch/copyright"
expect_line "$scratch/copyright" "Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/"
grep -qE '^License: [^ ]' "$scratch/copyright" || fail "the copyright file names no license"

dpkg-deb -I "$deb" >"$scratch/info"
field() { dpkg-deb -f "$deb" "$1"; }
[ "$(field Package)" = unima-bridge ] || fail "Package: $(field Package)"
[ "$(field Version)" = "$version" ] || fail "Version: $(field Version)"
[ "$(field Architecture)" = "$arch" ] || fail "Architecture: $(field Architecture)"
[ "$(field Section)" = net ] || fail "Section: $(field Section)"
[ -n "$(field Maintainer)" ] || fail "no Maintainer"
# What the daemon is, not only the Modbus TCP slave it was first.
description=$(field Description | tr -s " \n" " ")
for what in "Modbus RTU and TCP" "slave" "master" "gateway" "RS-485" "TLS" "captures" "monitor log" "MQTT" \
  "Home Assistant" "Sparkplug B" "HTTP"; do
  grep -qF -- "$what" <<<"$description" || fail "the description does not say '$what': $description"
done
depends=$(field Depends)
for lib in libc6 libstdc++6 libyaml-cpp0.7 libspdlog1.10 libfmt9 libsystemd0 libssl3 libmosquitto1 \
  "systemd | systemd-standalone-sysusers"; do
  grep -qF -- "$lib" <<<"$depends" || fail "Depends lacks $lib: $depends"
done
for script in postinst prerm postrm; do
  grep -qE "^ +[0-9]+ bytes, +[0-9]+ lines +\* +$script +#!/bin/sh" "$scratch/info" || { cat "$scratch/info" >&2; fail "no executable $script"; }
done
dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./conffiles >"$scratch/conffiles"
expect_line "$scratch/conffiles" /etc/unima-bridge/bridge.yaml

# The unit in the package runs the packaged daemon on the packaged config.
dpkg-deb --fsys-tarfile "$deb" | tar -xO ./usr/lib/systemd/system/unima-bridge.service >"$scratch/unit"
expect_line "$scratch/unit" "ExecStart=/usr/sbin/unima-bridged --config /etc/unima-bridge/bridge.yaml"
cmp -s "$scratch/unit" "$UNIMA_SOURCE_DIR/systemd/unima-bridge.service" || fail "the packaged unit differs from systemd/"

# Each program is an ELF file for the package's architecture (readelf's name of the machine).
case $arch in
  amd64) machine="Advanced Micro Devices X86-64" ;;
  arm64) machine="AArch64" ;;
  armhf) machine="ARM" ;;
  *) fail "no ELF machine known for $arch" ;;
esac
for program in usr/sbin/unima-bridged usr/bin/unima-bridge; do
  dpkg-deb --fsys-tarfile "$deb" | tar -xO "./$program" >"$scratch/program"
  found=$(readelf -h "$scratch/program" | sed -n 's/^ *Machine: *//p')
  [ "$found" = "$machine" ] || fail "$program is built for '$found', not $arch ($machine)"
done

# apt resolves another architecture's dependencies against that architecture's systemd,
# which this machine does not have: only this machine's package is simulated.
[ "$arch" = "$(dpkg --print-architecture)" ] || exit 0
apt-get install --simulate "$deb" >"$scratch/apt" 2>&1 || { cat "$scratch/apt" >&2; fail "apt cannot satisfy the dependencies"; }
