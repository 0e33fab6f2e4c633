#!/usr/bin/env bash
# The docs index lists every page: each docs/*.md is linked from docs/README.md, every link
# there names a page that exists, and the top-level README points at the index.
#   bash index.sh SOURCE_DIR
set -uo pipefail
cd "$1" || exit 1
fails=0
for f in docs/*.md; do
  n=${f#docs/}
  [ "$n" = README.md ] && continue
  grep -qF "]($n)" docs/README.md || { echo "FAIL: $f is not linked from docs/README.md"; fails=$((fails + 1)); }
done
for n in $(grep -o '](\([a-z0-9-]*\.md\))' docs/README.md | sed 's/^](//; s/)$//'); do
  [ -f "docs/$n" ] || { echo "FAIL: docs/README.md links $n, which does not exist"; fails=$((fails + 1)); }
done
grep -qF 'docs/README.md' README.md || { echo "FAIL: README.md does not point at docs/README.md"; fails=$((fails + 1)); }
[ "$fails" -eq 0 ] && echo "docs index: every page listed"
[ "$fails" -eq 0 ]
