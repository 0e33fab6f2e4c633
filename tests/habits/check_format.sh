#!/usr/bin/env bash
# scripts/check_format.sh against files whose formatting is known: a file written in the
# style passes, the same file with two lines broken the wrong way fails naming the file and
# the line, no list exempts a file (a leftover scripts/format-pending.txt is ignored), and
# nothing is rewritten.
#   bash check_format.sh SOURCE_DIR
set -uo pipefail
SRC=$1
fails=0
bad() { fails=$((fails + 1)); echo "FAIL: $*"; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
mkdir -p "$T/scripts" "$T/common"
cp "$SRC/.clang-format" "$T/"
cp "$SRC/scripts/check_format.sh" "$T/scripts/"
cat >"$T/common/good.c" <<'C'
/* Written by hand in the project's style. */
#include <math.h>

static double sq(double x) { return x * x; }

double hp_norm2(const double *v, int n)
{
    double s = 0.0;
    for (int k = 0; k < n; ++k) s += sq(v[k]);
    if (!(s >= 0.0)) return NAN; /* NaN stays NaN */
    return sqrt(s);
}
C
sed -e 's/^    double s = 0.0;/  double s=0.0;/' -e 's/^double hp_norm2(const double \*v, int n)$/double hp_norm2(const double *v, int n) {/' \
    -e '7d' "$T/common/good.c" >"$T/common/bad.c"
cp "$T/common/bad.c" "$T/bad.before"
cd "$T" || exit 1

bash scripts/check_format.sh common/good.c >out 2>err; rc=$?
[ "$rc" -eq 0 ] || bad "good.c: exit $rc, want 0 ($(cat out err))"

bash scripts/check_format.sh common/good.c common/bad.c >out 2>err; rc=$?
[ "$rc" -eq 1 ] || bad "bad.c: exit $rc, want 1"
grep -q '^common/bad.c:6:' out || bad "bad.c: no common/bad.c:6: line in: $(head -c 300 out)"
grep -q 'good.c' out && bad "good.c named as unformatted"
grep -q '1 of 2 files not formatted' err || bad "summary: $(cat err)"
cmp -s common/bad.c bad.before || bad "bad.c was rewritten"

echo common/bad.c >scripts/format-pending.txt
bash scripts/check_format.sh common/good.c common/bad.c >out 2>err; rc=$?
[ "$rc" -eq 1 ] || bad "bad.c listed in format-pending.txt: exit $rc, want 1 (no file is exempt)"
grep -q '^common/bad.c:6:' out || bad "listed bad.c not checked: $(head -c 300 out)"

bash scripts/check_format.sh common/good.c >out 2>err; rc=$?
grep -q '^check_format.sh: 1 files formatted$' out || bad "summary: $(cat out err)"

[ "$fails" -eq 0 ] && echo "check_format: all passed"
[ "$fails" -eq 0 ]
