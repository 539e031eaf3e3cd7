#!/usr/bin/env bash
# The first minutes of a newcomer (README's first two lines): scripts/demo.sh builds only
# what it runs, the daemon and the tool, not the tests and benchmarks; demo.sh and test.sh
# say how long each phase took; and no build command in README or docs/ starts unbounded
# jobs (`-j` without a number). The scripts run for real, with cmake, ctest, dpkg-query and
# the daemon replaced by stand-ins that record what they were asked.
. "$(dirname "$0")/lib.sh"
stubs="$scratch/stubs"
calls="$scratch/calls"
mkdir -p "$stubs" "$scratch/build/bin"
stub() {  # name, body
  printf '#!/usr/bin/env bash\necho "%s $*" >>"%s"\n%s\n' "$1" "$calls" "${2:-}" >"$stubs/$1"
  chmod +x "$stubs/$1"
}
stub cmake
stub ctest
stub clang++
stub dpkg-query 'echo "install ok installed"'
stub unima-bridged
mv "$stubs/unima-bridged" "$scratch/build/bin/unima-bridged"
run_script() {  # script, output file
  : >"$calls"
  PATH="$stubs:$PATH" BUILD_DIR="$scratch/build" FUZZ_BUILD_DIR="$scratch/fuzz" UNIMA_PHASE_REPORT="" \
    "$UNIMA_SOURCE_DIR/scripts/$1" >"$2" 2>&1 || { cat "$2" >&2; fail "scripts/$1 failed"; }
}
expect_phase() {  # output file, phase name
  grep -qE "^== $2: [0-9]+ s$" "$1" || { cat "$1" >&2; fail "no time for the phase '$2'"; }
  grep -qE "^ +$2 +[0-9]+ s$" "$1" || { cat "$1" >&2; fail "the summary lists no time for '$2'"; }
}

run_script demo.sh "$scratch/demo.out"
builds=$(grep '^cmake --build' "$calls") || fail "demo.sh built nothing: $(cat "$calls")"
while read -r line; do
  grep -qE -- ' -j ?[0-9]+( |$)' <<<"$line" || fail "demo.sh: a build without a bounded number of jobs: $line"
  targets=$({ grep -oE -- '--target [^ ]+' <<<"$line" || true; } | cut -d' ' -f2 | sort | tr '\n' ' ')
  [ "$targets" = "unima-bridge unima-bridged " ] ||
    fail "demo.sh must build the daemon and the tool only (what it runs), built: '${targets:-everything}' ($line)"
done <<<"$builds"
grep -qxF "unima-bridged --config config/examples/demo.yaml" "$calls" || fail "demo.sh did not run the daemon on demo.yaml"
for name in install configure build; do expect_phase "$scratch/demo.out" "$name"; done

# With stand-ins for cmake nothing can be packaged (the arm64 path's own test is
# packaging.package_arm64), but CI must run it after test.sh.
grep -qE '^scripts/test.sh$' "$UNIMA_SOURCE_DIR/.ci/run" || fail ".ci/run does not run scripts/test.sh"
grep -qE '^env -u BUILD_DIR scripts/package.sh arm64 --test$' "$UNIMA_SOURCE_DIR/.ci/run" ||
  fail ".ci/run does not run the arm64 path"
run_script test.sh "$scratch/test.out"
for name in install configure build tests "fuzz configure" "fuzz build" "fuzz run" bench; do
  expect_phase "$scratch/test.out" "$name"
done
grep -qE '^   total +[0-9]+ s$' "$scratch/test.out" || { cat "$scratch/test.out" >&2; fail "test.sh gives no total"; }

# Every build command a reader copies from the docs.
while IFS= read -r line; do
  grep -qE -- '-j( |$)' <<<"$line" && ! grep -qE -- '-j ?("?\$\(nproc\)"?|[0-9]+)' <<<"$line" &&
    fail "unbounded parallel build in the docs: $line"
done < <(grep -HnE 'cmake --build' "$UNIMA_SOURCE_DIR/README.md" "$UNIMA_SOURCE_DIR"/docs/*.md)
true
