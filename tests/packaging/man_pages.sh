#!/usr/bin/env bash
# The man pages render with man(1) and groff finds nothing to warn about.
. "$(dirname "$0")/lib.sh"
for page in "$UNIMA_SOURCE_DIR/docs/man/unima-bridged.8" "$UNIMA_SOURCE_DIR/docs/man/unima-bridge.1"; do
  name=$(basename "$page")
  MANWIDTH=80 man --warnings=w -l "$page" >"$scratch/$name.txt" 2>"$scratch/$name.err" || fail "man -l $page"
  if [ -s "$scratch/$name.err" ]; then cat "$scratch/$name.err" >&2; fail "warnings rendering $name"; fi
  grep -q '^NAME' "$scratch/$name.txt" && grep -q '^SYNOPSIS' "$scratch/$name.txt" || fail "$name lacks NAME or SYNOPSIS"
  grep -q "${name%.*} -" "$scratch/$name.txt" || fail "$name: no whatis line"
done
