#!/usr/bin/env bash
# The Debian maintainer scripts are POSIX sh that shellcheck finds nothing wrong with.
. "$(dirname "$0")/lib.sh"
for script in postinst prerm postrm; do
  f="$UNIMA_SOURCE_DIR/packaging/debian/$script"
  [ -x "$f" ] || fail "$f is not executable"
  head -n1 "$f" | grep -qx '#!/bin/sh' || fail "$f is not a /bin/sh script"
  shellcheck --shell=sh "$f" || fail "shellcheck $f"
done
