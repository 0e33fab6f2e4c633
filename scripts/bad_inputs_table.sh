#!/usr/bin/env bash
# Writes the table of docs/bad-inputs.md from tests/cli/bad_inputs.txt and the messages the
# program actually prints (it runs tests/cli/bad_inputs.sh with BAD_INPUTS_REPORT).
#   bash scripts/bad_inputs_table.sh HEADPLAN_BIN   (the Markdown table on stdout)
set -euo pipefail
BIN=$(realpath "$1"); SRC=$(cd "$(dirname "$0")/.." && pwd)
rep=$(mktemp); trap 'rm -f "$rep"' EXIT
BAD_INPUTS_REPORT=$rep bash "$SRC/tests/cli/bad_inputs.sh" "$BIN" "$SRC" >/dev/null ||
  { echo "bad_inputs_table: the catalogue fails; fix it first" >&2; exit 1; }
echo '| # | command line | exit | stderr (line 1, as observed) |'
echo '|---|---|---|---|'
n=0
while IFS= read -r line || [ -n "$line" ]; do
  case $line in '#'*|'') continue;; esac
  n=$((n+1))
  IFS='|' read -r _ _ args _ <<<"$line"
  args=$(echo $args)
  IFS=$'\t' read -r _ rc msg < <(sed -n "${n}p" "$rep")
  # Temporary paths and PIDs vary from run to run: show them as $T and PID.
  msg=$(sed -E "s#/tmp/[^/]*/bad#\$T#g; s#$SRC/scenarios#\$S#g; s#$SRC/tests/scenes_bad#\$B#g; s#partial-[0-9]+#partial-PID#g" <<<"$msg")
  esc() { sed 's/|/\\|/g; s/`/\\`/g' <<<"$1"; }
  printf '| %d | `headplan %s` | %s | %s |\n' "$n" "$(esc "$args")" "$rc" "$(esc "$msg")"
done <"$SRC/tests/cli/bad_inputs.txt"
