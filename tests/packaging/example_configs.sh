#!/usr/bin/env bash
# Every example config and the packaged default config pass `unima-bridge check`.
. "$(dirname "$0")/lib.sh"
configs=("$UNIMA_SOURCE_DIR"/config/examples/*.yaml "$UNIMA_SOURCE_DIR/packaging/bridge.yaml")
[ "${#configs[@]}" -ge 3 ] || fail "expected at least demo.yaml, chp-site.yaml and bridge.yaml"
for config in "${configs[@]}"; do
  "$UNIMA_BRIDGE_CLI" check --config "$config" || fail "check $config"
done
