#!/usr/bin/env bash
# The installed default config passes `check` and names every section and key the loader
# knows (commented out where it would need the site's data), so an operator finds each one
# where it goes. The list comes from the loader itself: `check` answers an unknown key
# with the keys it knows, so a key added to the loader fails here until it is in the file.
. "$(dirname "$0")/lib.sh"
config="$UNIMA_SOURCE_DIR/packaging/bridge.yaml"
"$UNIMA_BRIDGE_CLI" check --config "$config" >/dev/null || fail "check rejects $config"

# The keys the loader knows at PATH (e.g. "the config", "modbus", "modbus.tcp"), asked
# with the YAML in $1 whose innermost mapping holds an unknown key.
known_keys() {  # yaml, path as the loader names it
  printf '%b' "$1" >"$scratch/probe.yaml"
  { "$UNIMA_BRIDGE_CLI" check --config "$scratch/probe.yaml" 2>&1 || true; } |
    sed -n "s/.*unknown key 'zz_probe' in $2 (known: \(.*\))$/\1/p" | tr -d ',' | head -n1
}

# The lines of a top-level section, commented or not: from its header to the next one.
section_text() {  # section, every section
  awk -v section="$1" -v all=" $2 " '
    match($0, /^(# ?)?[a-z_]+:/) {
      key = substr($0, 1, RLENGTH - 1); sub(/^# ?/, "", key)
      if (index(all, " " key " ")) inside = (key == section)
    }
    inside' "$config"
}

sections=$(known_keys 'zz_probe: 1\n' 'the config')
[ "$(wc -w <<<"$sections")" -ge 12 ] || fail "could not learn the config's sections from check: '$sections'"
for section in $sections; do
  grep -qE "^(# ?)?$section:" "$config" || fail "$config has no '$section:' section, not even commented"
  text=$(section_text "$section" "$sections")
  # mqtt reads no other key before it has its broker.
  prelude=""; [ "$section" = mqtt ] && prelude='  broker: mqtt://127.0.0.1:1883\n'
  for key in $(known_keys "$section:\n${prelude}  zz_probe: 1\n" "$section"); do
    grep -qE "(^|[ #{,])$key:" <<<"$text" || fail "$config: section $section does not name '$key'"
    for subkey in $(known_keys "$section:\n${prelude}  $key:\n    zz_probe: 1\n" "$section\\.$key"); do
      grep -qE "(^|[ #{,])$subkey:" <<<"$text" || fail "$config: section $section does not name '$key.$subkey'"
    done
  done
done
