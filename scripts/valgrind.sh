#!/usr/bin/env bash
# Runs every test executable of the release build under valgrind memcheck; any error fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
export LC_ALL=C
cmake -S . -B build >/dev/null
cmake --build build -j"$(nproc)" >/dev/null
ctest --test-dir build -N -L 'iab|kinematics|scene|planner' >/dev/null
status=0
for t in build/tests/*_test_*; do
  [ -x "$t" ] || continue
  if valgrind --quiet --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=definite \
       --suppressions=tests/valgrind.supp "$t" >"build/$(basename "$t").vg.log" 2>&1; then
    echo "valgrind ok:   $(basename "$t")"
  else
    echo "valgrind FAIL: $(basename "$t") (build/$(basename "$t").vg.log)"; status=1
  fi
done
exit $status
