# --help lists exactly the words of the name tables: solve's --backend the backend table
# (planner/names.c, hpi_backend_words), its --level the level table (kinematics/names.c,
# hpi_level_words), in table order. The reference is read from the C tables themselves.
source "$2/tests/cli_lib.sh"
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")

table() { # the quoted words of table $2 in file $1, one per line
    python3 - "$1" "$2" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
m = re.search(re.escape(sys.argv[2]) + r"\[\]\s*=\s*\{(.*?)\};", text, re.S)
print("\n".join(re.findall(r'"([^"]*)"', m.group(1))))
PY
}
listed() { # the backend or level words an option's help text names, in order, one per line
    python3 - "$TMP/out" "$1" "$2" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
opt = re.search(r"^  " + re.escape(sys.argv[2]) + r" NAME (.*?)(?=^  --)", text, re.S | re.M)
words = sys.argv[3].split()
found = re.findall(r"[a-z][a-z-]*", opt.group(1)) if opt else []
print("\n".join(w for w in found if w in words))
PY
}

run solve --help
expect_exit 0 "solve --help"
backends=$(table "$HP_SRC/planner/names.c" hpi_backend_words)
levels=$(table "$HP_SRC/kinematics/names.c" hpi_level_words)
[ -n "$backends" ] && [ -n "$levels" ] && ok || bad "tables not read"
got=$(listed --backend "$backends" | awk '!seen[$0]++')
[ "$got" = "$backends" ] && ok || bad "solve --help --backend lists '$(echo $got)', the table '$(echo $backends)'"
got=$(listed --level "$levels" | awk '!seen[$0]++')
[ "$got" = "$levels" ] && ok || bad "solve --help --level lists '$(echo $got)', the table '$(echo $levels)'"
# The backend list is the table's, not a copy: no other backend-like word in it.
n=$(listed --backend "$backends" | wc -l)
[ "$n" -eq "$(echo "$backends" | wc -l)" ] || [ "$n" -eq $(( $(echo "$backends" | wc -l) + 1 )) ] \
    && ok || bad "solve --help --backend names $n backend words"
finish
