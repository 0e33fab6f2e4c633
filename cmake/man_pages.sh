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
# help2man names the page after the program it runs, and takes the SYNOPSIS from a first line
# "Usage: PROGRAM ..." (capitalised; the help prints "usage: headplan ..."). So each page runs
# a two-line wrapper, headplan or headplan-CMD, that capitalises that word on the first line.
wrapper() { # NAME ARGS...
  local name=$1; shift
  printf '#!/bin/sh\n"%s" %s "$@" | sed "1s/^usage:/Usage:/"\n' "$exe" "$*" >"$out/bin/$name"
  chmod +x "$out/bin/$name"
}
page() { # NAME SUMMARY
  help2man --no-info --version-string="$version" --name="$2" --output="$out/man1/$1.1" \
    "$out/bin/$1"
  grep -q '^\.SH SYNOPSIS$' "$out/man1/$1.1" ||
    { echo "man_pages.sh: $1 --help gives no usage line, so no SYNOPSIS" >&2; exit 1; }
}
wrapper headplan
page headplan "pressures for an eight-bladder soft head-stabilisation robot"
n=0
while read -r cmd summary; do
  [ -n "$cmd" ] || continue
  wrapper "headplan-$cmd" "$cmd"
  page "headplan-$cmd" "$summary"
  # help2man sets only the program's name in bold: the subcommand is part of the name too.
  perl -0pi -e "s/^\\.B headplan\n\\\\fI\\\\,\Q$cmd\E /.B \"headplan $cmd\"\n\\\\fI\\\\,/m" \
    "$out/man1/headplan-$cmd.1"
  n=$((n + 1))
done < <("$exe" --help | sed -n '/^commands:$/,/^$/p' | sed '1d')
[ "$n" -ge 1 ] || { echo "man_pages.sh: no subcommand in '$exe --help'" >&2; exit 1; }
