#!/usr/bin/env bash
# The man pages render with man(1) and groff finds nothing to warn about, and each names
# exactly the subcommands and options its program's --help names (man_vs_help.py).
. "$(dirname "$0")/lib.sh"
python3 "$(dirname "$0")/man_vs_help.py" "$UNIMA_SOURCE_DIR/docs/man/unima-bridge.1" "$UNIMA_BRIDGE_CLI" ||
  fail "unima-bridge(1) and unima-bridge --help differ"
python3 "$(dirname "$0")/man_vs_help.py" "$UNIMA_SOURCE_DIR/docs/man/unima-bridged.8" "$UNIMA_BRIDGED" ||
  fail "unima-bridged(8) and unima-bridged --help differ"
for page in "$UNIMA_SOURCE_DIR/docs/man/unima-bridged.8" "$UNIMA_SOURCE_DIR/docs/man/unima-bridge.1"; do
  name=$(basename "$page")
  MANWIDTH=80 man --warnings=w -l "$page" >"$scratch/$name.txt" 2>"$scratch/$name.err" || fail "man -l $page"
  if [ -s "$scratch/$name.err" ]; then cat "$scratch/$name.err" >&2; fail "warnings rendering $name"; fi
  grep -q '^NAME' "$scratch/$name.txt" && grep -q '^SYNOPSIS' "$scratch/$name.txt" || fail "$name lacks NAME or SYNOPSIS"
  grep -q "${name%.*} -" "$scratch/$name.txt" || fail "$name: no whatis line"
done
# unima-bridged(8) says what the daemon is, not only the Modbus TCP slave it was first.
for what in "Modbus RTU and TCP" "slave" "master" "gateway" "RS-485" "TLS" "captures" "monitor log" "MQTT" "Home Assistant" \
  "Sparkplug B" "HTTP" "front page"; do
  tr -s ' \n' ' ' <"$scratch/unima-bridged.8.txt" | grep -qF -- "$what" || fail "unima-bridged(8) does not say '$what'"
done
