#!/usr/bin/env bash
# The unit's hardening: `systemd-analyze security --offline` must rate the exposure 2.0 or less.
. "$(dirname "$0")/lib.sh"
limit=2.0
unit="$UNIMA_SOURCE_DIR/systemd/unima-bridge.service"
report=$(systemd-analyze security --offline=true --no-pager "$unit" 2>&1) || { echo "$report"; fail "systemd-analyze security"; }
exposure=$(sed -n 's/.*Overall exposure level for unima-bridge.service: \([0-9.]*\).*/\1/p' <<<"$report")
[ -n "$exposure" ] || { echo "$report"; fail "no overall exposure level in the report"; }
echo "exposure $exposure (limit $limit)"
awk -v e="$exposure" -v l="$limit" 'BEGIN { exit !(e <= l) }' || { echo "$report"; fail "exposure $exposure is above $limit"; }
