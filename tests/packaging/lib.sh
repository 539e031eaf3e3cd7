# shellcheck shell=bash
# Shared by the packaging tests (sourced). CTest sets UNIMA_SOURCE_DIR, UNIMA_BUILD_DIR,
# UNIMA_BRIDGE_CLI, UNIMA_BRIDGED and UNIMA_DEB_DIR.
set -euo pipefail

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# A temp dir removed when the test ends.
scratch=$(mktemp -d "${TMPDIR:-/tmp}/unima-packaging-XXXXXX")
trap 'rm -rf "$scratch"' EXIT

# Installs the build tree under $1 as `cmake --install --prefix` does, quietly.
install_to() {
  cmake --install "$UNIMA_BUILD_DIR" --prefix "$1" >"$scratch/install.log" 2>&1 ||
    { cat "$scratch/install.log" >&2; fail "cmake --install --prefix $1"; }
}

expect_file() {
  [ -f "$1" ] || fail "missing $1"
}

expect_line() {  # file, exact line
  grep -qxF -- "$2" "$1" || { cat "$1" >&2; fail "$1 has no line '$2'"; }
}
