#!/usr/bin/env bash
# The quickstart's package build (docs/quickstart.md, step 1) builds only what the package
# ships: configured with its own command line, the build has no test, benchmark, simulator
# or developer tool among its targets.
. "$(dirname "$0")/lib.sh"
configure=$(grep -m1 '^cmake -S \. -B build-release ' "$UNIMA_SOURCE_DIR/docs/quickstart.md") ||
  fail "docs/quickstart.md has no 'cmake -S . -B build-release' line"
read -ra words <<<"${configure%%#*}"
[ "${words[4]}" = build-release ] || fail "unexpected configure line: $configure"
words[2]="$UNIMA_SOURCE_DIR"; words[4]="$scratch/build"
"${words[@]}" >"$scratch/configure.log" 2>&1 || { cat "$scratch/configure.log" >&2; fail "$configure"; }
cmake --build "$scratch/build" --target help >"$scratch/help" 2>&1 || { cat "$scratch/help" >&2; fail "no target list"; }
# The project's targets: libraries are unima_*, besides them only the two programs and the man pages.
sed -n 's/^\.\.\. \([^ ]*\).*/\1/p' "$scratch/help" >"$scratch/targets"
built=$(grep -vxE 'all|clean|depend|edit_cache|install|install/local|install/strip|list_install_components|package|package_source|rebuild_cache|test' \
  "$scratch/targets" | grep -v '^unima_' | grep -vE '\.(o|i|s)$' | sort | tr '\n' ' ')
[ "$built" = "man_pages unima-bridge unima-bridged " ] || fail "the package build also builds: $built"
if grep -E 'test|bench|sim' "$scratch/targets" | grep -vxE 'test' >&2; then fail "test, benchmark or simulator libraries in the package build"; fi
echo "the package build makes: $built"
