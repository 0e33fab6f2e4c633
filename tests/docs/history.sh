#!/usr/bin/env bash
# The docs say what is true now: no tracked Markdown file holds a dated log line
# (YYYY-MM-DD) or a history phrase ("used to", "was fixed", ": fixed"), except CHANGELOG.md,
# which keeps the history, and docs/measurements.md, which dates the one run every measured
# number comes from. Prints FILE:LINE: TEXT for each and exits 1 when there is any. The
# checker's own patterns are tried first on lines of known verdict.
#   bash history.sh SOURCE_DIR
set -uo pipefail
cd "$1" || exit 2
DATE='\b(19|20)[0-9]{2}-(0[1-9]|1[0-2])-(0[1-9]|[12][0-9]|3[01])\b'
HIST='(?<!\bis )(?<!\bare )(?<!\bbe )(?<!\bbeen )(?<!\bbeing )\bused to\b|\b(was|were|been|is now|are now|got) fixed\b|: fixed\b'
hits() { grep -n -H -i -P "$DATE|$HIST" "$@"; }

fails=0
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
printf '%s\n' 'Run of 2026-11-23: 12 s.' 'It used to take 9 ms.' 'The overflow was fixed.' \
  'a buffer overrun: fixed, tests/x.c' >"$T/bad.md"
printf '%s\n' 'The seed is used to draw targets.' 'A fixed seed; 12-3-4 is no date.' \
  'Fixed Gauss-Legendre nodes.' >"$T/good.md"
[ "$(hits "$T/bad.md" | wc -l)" -eq 4 ] || { echo "FAIL: the checker misses a bad line: $(hits "$T/bad.md")"; fails=1; }
if hits "$T/good.md"; then echo "FAIL: the checker flags a line that is no history"; fails=1; fi

mapfile -t files < <(git ls-files '*.md' | grep -v -x -e CHANGELOG.md -e docs/measurements.md)
[ "${#files[@]}" -ge 10 ] || { echo "FAIL: only ${#files[@]} Markdown files found"; exit 1; }
if hits "${files[@]}"; then
  echo "FAIL: the lines above date a log or tell history: history goes to CHANGELOG.md, a" \
       "run's date to docs/measurements.md (bash scripts/regen-docs.sh)"
  fails=1
fi
[ "$fails" -eq 0 ] && echo "docs_history: ${#files[@]} files, no dated log line or history phrase"
[ "$fails" -eq 0 ]
