#!/usr/bin/env bash
# The sysusers.d and tmpfiles.d files, applied to an empty root: a system user with no
# login, in dialout; the monitor's log directory, not world-readable.
. "$(dirname "$0")/lib.sh"
root="$scratch/root"
mkdir -p "$root/etc"
systemd-sysusers --root="$root" "$UNIMA_SOURCE_DIR/systemd/unima-bridge.sysusers"
passwd_line=$(grep '^unima-bridge:' "$root/etc/passwd") || fail "no user unima-bridge"
IFS=: read -r _ _ uid _ _ home shell <<<"$passwd_line"
[ "$uid" -lt 1000 ] || fail "uid $uid is not a system uid"
[ "$home" = /var/lib/unima-bridge ] || fail "home $home"
[ "$shell" = /usr/sbin/nologin ] || fail "shell $shell"
grep -q '^dialout:.*:\(.*,\)\?unima-bridge\(,.*\)\?$' "$root/etc/group" || fail "unima-bridge is not in dialout"

# Exit 73 (cannot chown) is expected when the test does not run as root.
status=0
systemd-tmpfiles --root="$root" --create "$UNIMA_SOURCE_DIR/systemd/unima-bridge.tmpfiles" || status=$?
[ "$status" -eq 0 ] || { [ "$status" -eq 73 ] && [ "$(id -u)" -ne 0 ]; } || fail "systemd-tmpfiles exit $status"
[ "$(stat -c %a "$root/var/log/unima-bridge")" = 750 ] || fail "log directory mode $(stat -c %a "$root/var/log/unima-bridge")"
