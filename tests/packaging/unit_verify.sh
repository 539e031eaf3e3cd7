#!/usr/bin/env bash
# `systemd-analyze verify` on the unit as installed. verify needs the ExecStart binary and
# the Documentation= man pages to exist, so it runs on an install under a temp prefix (whose
# unit names that prefix's unima-bridged), with MANPATH at the installed man pages.
# verify exits 0 after "Unknown key" and like warnings, so any output fails the test.
. "$(dirname "$0")/lib.sh"

verify() {  # unit file; prints what systemd-analyze said
  MANPATH="$prefix/share/man" systemd-analyze verify "$1" 2>&1 || echo "exit status $?"
}

prefix="$scratch/prefix"
install_to "$prefix"
unit="$prefix/lib/systemd/system/unima-bridge.service"
expect_line "$unit" "ExecStart=$prefix/sbin/unima-bridged --config $prefix/etc/unima-bridge/bridge.yaml"
said=$(verify "$unit")
[ -z "$said" ] || { echo "$said" >&2; fail "systemd-analyze verify $unit"; }

# and verify does catch a broken unit the way this test reads it
sed 's/^Type=notify$/Typo=notify/' "$unit" >"$scratch/unima-bridge.service"
[ -n "$(verify "$scratch/unima-bridge.service")" ] || fail "verify said nothing about Typo=notify"
