#!/usr/bin/env bash
# The test tree keeps one home for what the tests share and names its files by subject:
# - the seeded generator (splitmix64, recognised by its finaliser's multiplier) is written only
#   in tests/support/rng.h, never copied into a test, the benchmark lab or an example;
# - no test file is named by the round it was written in (seams2.sh, test_x3.c): a name ends
#   in a word, not a number.
# Usage: test_tree_test.sh SOURCE_DIR
set -uo pipefail
src="$1"; fails=0
copies=$(grep -rlI --include='*.c' --include='*.cpp' --include='*.h' 'BF58476D1CE4E5B9' \
         "$src/tests" "$src/bench" "$src/python" "$src/fuzz" 2>/dev/null \
         | grep -v '/tests/support/rng\.h$' | sed "s|^$src/||")
if [ -n "$copies" ]; then
  echo "FAIL: splitmix64 written outside tests/support/rng.h: $(tr '\n' ' ' <<<"$copies")"
  fails=$((fails + 1))
fi
rounds=$(cd "$src" && find tests python/tests -type f \( -name '*.sh' -o -name '*.c' -o -name '*.py' \) \
         -name '*[0-9].*' ! -name 'test_sha256.c' | sort)
if [ -n "$rounds" ]; then
  echo "FAIL: test files named by a number, not a subject: $(tr '\n' ' ' <<<"$rounds")"
  fails=$((fails + 1))
fi
[ -f "$src/tests/support/rng.h" ] || { echo "FAIL: no tests/support/rng.h"; fails=$((fails + 1)); }
echo "$((3 - fails)) passed, $fails failed"
[ "$fails" -eq 0 ]
