#!/usr/bin/env bash
# Writes the man pages of `headplan` and of each of its subcommands, from their --help, so a
# page cannot disagree with the program (help2man). The subcommands are read from
# `headplan --help` (its "commands:" list), so a new one gets its page without a change here.
#   man_pages.sh HEADPLAN OUT_DIR VERSION      -> OUT_DIR/man1/headplan.1, headplan-CMD.1
set -euo pipefail
exe="$1"; out="$2"; version="$3"
rm -rf "$out/man1" "$out/bin"
mkdir -p "$out/man1" "$out/bin"
export LC_ALL=C
page() { # NAME SUMMARY PROGRAM
  help2man --no-info --version-string="$version" --name="$2" --output="$out/man1/$1.1" "$3"
}
page headplan "pressures for an eight-bladder soft head-stabilisation robot" "$exe"
n=0
while read -r cmd summary; do
  [ -n "$cmd" ] || continue
  # help2man names the page after the program it runs: a two-line wrapper headplan-CMD.
  printf '#!/bin/sh\nexec "%s" %s "$@"\n' "$exe" "$cmd" >"$out/bin/headplan-$cmd"
  chmod +x "$out/bin/headplan-$cmd"
  page "headplan-$cmd" "$summary" "$out/bin/headplan-$cmd"
  n=$((n + 1))
done < <("$exe" --help | sed -n '/^commands:$/,/^$/p' | sed '1d')
[ "$n" -ge 1 ] || { echo "man_pages.sh: no subcommand in '$exe --help'" >&2; exit 1; }
