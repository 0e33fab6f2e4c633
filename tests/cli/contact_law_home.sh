#!/usr/bin/env bash
# The contact law has one home (kinematics/contact_law.c): no other C source of the product,
# the benchmark lab or the Python module multiplies pi by the bladder radius or the contact
# distance (the cap law's area pi·(ro² − rho²) and its derivatives 2·pi·P·ro, −2·pi·P·rho
# were once written in five files).
source "$2/tests/cli_lib.sh"
pat='(\bPI\b|HP_PI|M_PI).*(\b(ro|rho)\b|rho\[)|(\b(ro|rho)\b|rho\[).*(\bPI\b|HP_PI|M_PI)'
scan() { (cd "$1" && grep -rnE --include='*.c' --include='*.h' "$pat" \
          common iab kinematics planner scene calib horizon cli bench python 2>/dev/null |
          grep -v '^kinematics/contact_law\.[ch]:' | grep -vE '^[^:]*:[0-9]+:\s*(/?\*|//)'); }
if scan "$HP_SRC" >"$TMP/out"; then bad "the contact law written outside kinematics/contact_law.c"
  cat "$TMP/out"; else ok; fi
# The scan finds a copy (it is not vacuous).
mkdir -p "$TMP/tree/planner"
printf 'double f(double P, double ro, double rho) { return P * HP_PI * (ro - rho) * (ro + rho); }\n' \
  >"$TMP/tree/planner/x.c"
scan "$TMP/tree" >/dev/null && ok || bad "the scan misses a copy of the law"
finish
