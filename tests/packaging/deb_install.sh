#!/usr/bin/env bash
# Installs the .deb with dpkg into an empty root (dpkg --root, maintainer scripts run
# with DPKG_ROOT), then upgrades over an edited config, then purges: the user, the enabled
# unit, the log directory, the conffile kept, everything gone after purge but the user.
. "$(dirname "$0")/lib.sh"
deb=$(ls "$UNIMA_DEB_DIR"/unima-bridge_*.deb)
root="$scratch/root"
mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates" "$root/etc"
touch "$root/var/lib/dpkg/status"
dpkg_root() {
  # --force-depends: the empty root has no libc; --force-not-root: chown is not ours to do.
  dpkg --root="$root" --force-script-chrootless --force-depends --force-not-root "$@" >>"$scratch/dpkg.log" 2>&1 ||
    { cat "$scratch/dpkg.log" >&2; fail "dpkg $*"; }
}

dpkg_root --install "$deb"
grep -q '^unima-bridge:.*:/var/lib/unima-bridge:/usr/sbin/nologin$' "$root/etc/passwd" || fail "postinst made no user"
grep -q '^dialout:.*unima-bridge' "$root/etc/group" || fail "the user is not in dialout"
[ -L "$root/etc/systemd/system/multi-user.target.wants/unima-bridge.service" ] || fail "the unit is not enabled"
[ -d "$root/var/log/unima-bridge" ] || fail "no /var/log/unima-bridge"
status=$(dpkg --root="$root" -s unima-bridge)
grep -qx 'Status: install ok installed' <<<"$status" || fail "not installed: $status"
grep -q '^ /etc/unima-bridge/bridge.yaml [0-9a-f]\{32\}$' <<<"$status" || fail "bridge.yaml is not a conffile: $status"
# The installed programs run on this Debian 12 with the installed default config.
"$root/usr/bin/unima-bridge" check --config "$root/etc/unima-bridge/bridge.yaml" >/dev/null ||
  fail "the installed check rejects the installed config"
"$root/usr/sbin/unima-bridged" --version | grep -q '^unima-bridged ' || fail "unima-bridged --version"

echo "# edited by the operator" >>"$root/etc/unima-bridge/bridge.yaml"
dpkg_root --install "$deb"
tail -n1 "$root/etc/unima-bridge/bridge.yaml" | grep -qx "# edited by the operator" || fail "an upgrade replaced the edited config"

dpkg_root --purge unima-bridge
for gone in etc/unima-bridge usr/sbin/unima-bridged usr/lib/systemd/system/unima-bridge.service var/log/unima-bridge \
            etc/systemd/system/multi-user.target.wants/unima-bridge.service; do
  [ ! -e "$root/$gone" ] || fail "/$gone is still there after purge"
done
# As docs/operations.md says: the system user stays, as Debian leaves system users behind.
grep -q '^unima-bridge:' "$root/etc/passwd" || fail "purge removed the system user, which docs/operations.md says stays"
