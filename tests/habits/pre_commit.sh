#!/usr/bin/env bash
# scripts/pre-commit in a scratch repository: a staged file in the style that compiles passes;
# one whose format is off, or that does not compile with its compile_commands.json flags,
# or that includes a module above its own, makes the hook fail and say which file.
#   bash pre_commit.sh SOURCE_DIR
set -uo pipefail
SRC=$1
fails=0
bad() { fails=$((fails + 1)); echo "FAIL: $*"; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
mkdir -p "$T/cmake" "$T/scripts" "$T/common" "$T/planner" "$T/build" "$T/include/headplan"
cp "$SRC/.clang-format" "$T/"
cp "$SRC/cmake/layers.txt" "$T/cmake/"
cp "$SRC/scripts/pre-commit" "$SRC/scripts/check_format.sh" "$SRC/scripts/check_layers.py" "$T/scripts/"
cd "$T" || exit 1
git init -q . && git config user.email t@t && git config user.name t
cat >common/ok.c <<'C'
/* In the style, and compiles. */
int hp_ok(int x);

int hp_ok(int x) { return x + 1; }
C
cat >build/compile_commands.json <<J
[{"directory": "$T/build", "file": "$T/common/ok.c",
  "command": "cc -std=c11 -Wall -Wextra -Werror -Wmissing-prototypes -c $T/common/ok.c -o ok.o"}]
J
git add common/ok.c
bash scripts/pre-commit >out 2>&1; rc=$?
[ "$rc" -eq 0 ] || bad "good file: exit $rc: $(cat out)"
grep -q '1 files compiled, 0 failed' out || bad "good file: no compile line: $(cat out)"

printf 'int hp_ok(int x);\n\nint hp_ok(int x) {   return x+1; }\n' >common/ok.c
git add common/ok.c
bash scripts/pre-commit >out 2>&1; rc=$?
[ "$rc" -ne 0 ] || bad "unformatted file: exit 0"
grep -q '^common/ok.c:3:' out || bad "unformatted file: not named: $(cat out)"

printf '/* No prototype. */\nint hp_ok(int x) { return x + 1; }\n' >common/ok.c
git add common/ok.c
bash scripts/pre-commit >out 2>&1; rc=$?
[ "$rc" -ne 0 ] || bad "missing prototype: exit 0"
grep -q '1 files compiled, 1 failed' out || bad "missing prototype: not reported: $(cat out)"

printf '/* In the style, and compiles. */\nint hp_ok(int x);\n\nint hp_ok(int x) { return x + 1; }\n' >common/ok.c
printf '#include "planner/p.h"\n' >common/up.h
printf '/* A planner header. */\n' >planner/p.h
git add common/ok.c common/up.h planner/p.h
bash scripts/pre-commit >out 2>&1; rc=$?
[ "$rc" -ne 0 ] || bad "upward include: exit 0"
grep -q 'common/up.h' out || bad "upward include: not named: $(cat out)"

[ "$fails" -eq 0 ] && echo "pre_commit: all passed"
[ "$fails" -eq 0 ]
