#!/usr/bin/env bash
# `cmake --install --prefix DIR` without root: every file in its place under the prefix,
# the unit pointing at that prefix, and an operator's edited config kept on reinstall.
. "$(dirname "$0")/lib.sh"
prefix="$scratch/prefix"
install_to "$prefix"
for f in sbin/unima-bridged bin/unima-bridge \
         lib/systemd/system/unima-bridge.service lib/sysusers.d/unima-bridge.conf lib/tmpfiles.d/unima-bridge.conf \
         etc/unima-bridge/bridge.yaml share/man/man8/unima-bridged.8.gz share/man/man1/unima-bridge.1.gz \
         share/doc/unima-bridge/README.md share/doc/unima-bridge/docs/images/front-page.png \
         share/doc/unima-bridge/examples/bridge.yaml share/doc/unima-bridge/examples/chp-site.yaml; do
  expect_file "$prefix/$f"
done
for doc in "$UNIMA_SOURCE_DIR"/docs/*.md; do
  expect_file "$prefix/share/doc/unima-bridge/$(basename "$doc")"
done
[ -x "$prefix/sbin/unima-bridged" ] && [ -x "$prefix/bin/unima-bridge" ] || fail "programs not executable"
MANWIDTH=80 man -l "$prefix/share/man/man8/unima-bridged.8.gz" >"$scratch/man.txt"
grep -q "^NAME" "$scratch/man.txt" || fail "the installed man page does not render"
cmp -s "$UNIMA_SOURCE_DIR/packaging/bridge.yaml" "$prefix/etc/unima-bridge/bridge.yaml" || fail "default config differs"
unit="$prefix/lib/systemd/system/unima-bridge.service"
expect_line "$unit" "ExecStart=$prefix/sbin/unima-bridged --config $prefix/etc/unima-bridge/bridge.yaml"
if grep -Eq '(^|[ =])(/usr/sbin/|/etc/unima-bridge)' "$unit"; then fail "the unit still names the package's paths"; fi
"$prefix/bin/unima-bridge" check --config "$prefix/etc/unima-bridge/bridge.yaml" >/dev/null ||
  fail "the installed default config does not pass check"

echo "# edited by the operator" >>"$prefix/etc/unima-bridge/bridge.yaml"
install_to "$prefix"
tail -n1 "$prefix/etc/unima-bridge/bridge.yaml" | grep -qx "# edited by the operator" ||
  fail "a reinstall overwrote the operator's config"
grep -q "Keeping: $prefix/etc/unima-bridge/bridge.yaml" "$scratch/install.log" || fail "no word about the kept config"
