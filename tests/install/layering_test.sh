#!/usr/bin/env bash
# The layering holds: no include runs back up the data flow or sideways to a module not used
# (scripts/check_layers.py, against cmake/layers.txt), no two files of a folder depend on each
# other, and the bladder module's tests were linked with no Ipopt, NLopt or YAML library (what
# the dynamic loader would load for them, ldd). Usage: layering_test.sh BUILD_DIR SOURCE_DIR
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
# The private layer is visible: every hp_* symbol the library defines is a public function
# (scripts/hp_api.py list); internal functions and tables are named hpi_*.
if [ -f "$build/libheadplan.a" ]; then
  extra=$(nm "$build/libheadplan.a" 2>/dev/null | awk '$2 ~ /^[TtDdRrBb]$/ && $3 ~ /^hp_/ {print $3}' |
          sed 's/\..*$//' | sort -u |
          comm -23 - <(python3 "$src/scripts/hp_api.py" list "$src"/include/headplan/*.h | sort -u))
  [ -z "$extra" ] || { echo "FAIL: internal names with the public prefix hp_: $(tr '\n' ' ' <<<"$extra")"; fails=$((fails + 1)); }
else
  echo "FAIL: no $build/libheadplan.a"; fails=$((fails + 1))
fi
# The umbrella is complete: headplan.h includes every public header (hp_load_planner.h aside,
# whose load planner becomes a level of hp_planner).
for h in "$src"/include/headplan/hp_*.h "$src"/include/headplan/hp_version.h.in; do
  h=$(basename "$h" .in)
  [ "$h" = hp_load_planner.h ] && continue
  grep -q "#include \"headplan/$h\"" "$src/include/headplan/headplan.h" ||
    { echo "FAIL: headplan.h does not include $h"; fails=$((fails + 1)); }
done
# The checker is not vacuous: an upward include in a scratch tree is found.
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/iab" "$tmp/include/headplan" "$tmp/cmake"
cp "$src/cmake/layers.txt" "$tmp/cmake/layers.txt"
printf '#include "planner/problem.h"\n' >"$tmp/iab/x.c"
python3 "$src/scripts/check_layers.py" "$tmp" >/dev/null && { echo "FAIL: the checker missed iab -> planner"; fails=$((fails + 1)); }
# Nor blind to a cycle between two files of one folder (a.c calls b.c, which calls a.c back),
# while a one-way call is fine.
mkdir -p "$tmp/calib"
rm "$tmp/iab/x.c"
printf 'int hp_b(int x);\nint hp_a(int x)\n{\n    return x > 0 ? hp_b(x - 1) : 0;\n}\n' >"$tmp/calib/a.c"
printf 'int hp_b(int x)\n{\n    return x + 1;\n}\n' >"$tmp/calib/b.c"
python3 "$src/scripts/check_layers.py" "$tmp" >/dev/null || { echo "FAIL: the checker refused a one-way call"; fails=$((fails + 1)); }
printf 'int hp_a(int x);\nint hp_b(int x)\n{\n    return hp_a(x) + 1; /* hp_c() */\n}\n' >"$tmp/calib/b.c"
out=$(python3 "$src/scripts/check_layers.py" "$tmp")
grep -q 'calib/: the files a.c, b.c depend on each other' <<<"$out" || { echo "FAIL: the checker missed the cycle calib/a.c <-> calib/b.c"; fails=$((fails + 1)); }
# Nor blind to a sideways include: horizon does not use calib (cmake/layers.txt).
rm "$tmp/calib/"*.c; mkdir -p "$tmp/horizon"
printf '#include "calib/calib_internal.h"\n' >"$tmp/horizon/x.c"
python3 "$src/scripts/check_layers.py" "$tmp" >/dev/null && { echo "FAIL: the checker missed horizon -> calib"; fails=$((fails + 1)); }
# Nor blind to a module's internal header included by another module that is not on the
# private layer's list (cmake/private_headers.txt): scene uses planner, but
# planner/load_qp.h is planner's own; planner/names.h is on the list.
rm "$tmp/horizon/x.c"; mkdir -p "$tmp/scene" "$tmp/planner"
cp "$src/cmake/private_headers.txt" "$tmp/cmake/private_headers.txt"
printf '#include "planner/names.h"\n' >"$tmp/scene/x.c"
python3 "$src/scripts/check_layers.py" "$tmp" >/dev/null || { echo "FAIL: the checker refused a listed private header"; fails=$((fails + 1)); }
printf '#include "planner/load_qp.h"\n' >"$tmp/scene/x.c"
out=$(python3 "$src/scripts/check_layers.py" "$tmp")
grep -q 'scene/x.c: includes planner/load_qp.h, an internal header of planner not in the private layer' <<<"$out" || { echo "FAIL: the checker missed scene -> planner/load_qp.h"; fails=$((fails + 1)); }
echo "$((n + 7 - fails)) passed, $fails failed"
[ "$fails" -eq 0 ]
