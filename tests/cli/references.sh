#!/usr/bin/env bash
# The docs stand on their own: every document (*.md) the tree mentions, and every path the
# Markdown docs mention, exists in the repository (scripts/check_refs.py); nothing refers to
# a file outside it.
source "$2/tests/cli_lib.sh"
if python3 "$HP_SRC/scripts/check_refs.py" "$HP_SRC" >"$TMP/out" 2>"$TMP/err"; then ok; else
  bad "references to files that are not in the repository ($(wc -l <"$TMP/out") found)"
  head -20 "$TMP/out"
fi
# The checker itself finds a missing reference (it is not vacuous).
mkdir -p "$TMP/tree/docs"
ext=md  # spelled through a variable so that this file itself mentions no missing document
printf 'See NOTES.%s and ../outside/FACTS.%s.\n' "$ext" "$ext" >"$TMP/tree/docs/a.$ext"
python3 "$HP_SRC/scripts/check_refs.py" "$TMP/tree" >"$TMP/out" 2>"$TMP/err"
[ $? -eq 1 ] && grep -q "NOTES.$ext" "$TMP/out" && grep -q "outside" "$TMP/out" && ok ||
  bad "the checker misses a reference to a missing file"
finish
