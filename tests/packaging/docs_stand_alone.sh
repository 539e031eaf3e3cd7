#!/usr/bin/env bash
# The repository stands alone: the README, docs/ and the man pages point at nothing outside
# it (no specification kept elsewhere), and every relative link of a document resolves.
. "$(dirname "$0")/lib.sh"
cd "$UNIMA_SOURCE_DIR"
pages=(README.md docs/*.md docs/man/*)
if grep -nE 'SPEC(\.md| §|\b)|\.\./shared' "${pages[@]}" >"$scratch/outside"; then
  cat "$scratch/outside" >&2
  fail "documents point at a specification outside the repository"
fi
broken=0
for page in README.md docs/*.md; do
  # Markdown links [text](target), without a scheme or an anchor alone.
  while IFS= read -r target; do
    target=${target%%#*}
    [ -n "$target" ] || continue
    [ -e "$(dirname "$page")/$target" ] || { echo "$page: link to $target, which is not there" >&2; broken=1; }
  done < <(grep -oE '\]\([^)[:space:]]+\)' "$page" | sed 's/^](\(.*\))$/\1/' | grep -vE '^[a-z]+:')
done
[ "$broken" -eq 0 ] || fail "broken links"
echo "${#pages[@]} documents stand alone"
