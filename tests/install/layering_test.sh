#!/usr/bin/env bash
# The layering holds: no include runs back up the data flow (scripts/check_layers.py), and
# the bladder module's tests were linked with no Ipopt, NLopt or YAML library (what the
# dynamic loader would load for them, ldd). Usage: layering_test.sh BUILD_DIR SOURCE_DIR
set -uo pipefail
build="$1"; src="$2"; fails=0
python3 "$src/scripts/check_layers.py" "$src" || { echo "FAIL: an include runs back up"; fails=$((fails + 1)); }
n=0
for t in "$build"/tests/iab_test_*; do
  [ -x "$t" ] || continue
  n=$((n + 1))
  if ldd "$t" | grep -Eiq 'ipopt|nlopt|yaml|jansson|mumps'; then
    echo "FAIL: $(basename "$t") links $(ldd "$t" | grep -Eio 'lib(ipopt|nlopt|yaml|jansson|mumps)[^ ]*' | tr '\n' ' ')"
    fails=$((fails + 1))
  fi
done
[ "$n" -ge 3 ] || { echo "FAIL: only $n bladder-module test programs found in $build/tests"; fails=$((fails + 1)); }
# The checker is not vacuous: an upward include in a scratch tree is found.
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/iab" "$tmp/include/headplan"
printf '#include "planner/problem.h"\n' >"$tmp/iab/x.c"
python3 "$src/scripts/check_layers.py" "$tmp" >/dev/null && { echo "FAIL: the checker missed iab -> planner"; fails=$((fails + 1)); }
echo "$((n + 2 - fails)) passed, $fails failed"
[ "$fails" -eq 0 ]
