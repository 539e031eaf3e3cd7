#!/usr/bin/env bash
# Fixture of the .deb tests: runs CPack on the build tree in a temp dir and leaves the
# package in $UNIMA_DEB_DIR.
. "$(dirname "$0")/lib.sh"
rm -rf "$UNIMA_DEB_DIR"
mkdir -p "$UNIMA_DEB_DIR"
(cd "$scratch" && cpack --config "$UNIMA_BUILD_DIR/CPackConfig.cmake" -G DEB -B "$scratch/cpack") >"$scratch/cpack.log" 2>&1 ||
  { cat "$scratch/cpack.log" >&2; fail "cpack"; }
debs=("$scratch"/cpack/*.deb)
[ "${#debs[@]}" -eq 1 ] && [ -f "${debs[0]}" ] || { cat "$scratch/cpack.log" >&2; fail "expected one .deb, got: ${debs[*]}"; }
mv "${debs[0]}" "$UNIMA_DEB_DIR/"
echo "built $(basename "${debs[0]}")"
