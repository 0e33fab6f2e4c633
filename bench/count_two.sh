# Sourced by bench/plan_ab.sh and bench/plan_bits.sh (NAME A B set): checks that folders A
# and B hold a libheadplan.so, compiles bench/plan_count.c once against this tree's headers
# into $tmp/count (tmp removed on exit; inc: the include flags), and defines run LIBDIR
# ARGS... (headplan-bench-count on the default scene against that folder's library).
for d in "$A" "$B"; do
  [ -e "$d/libheadplan.so" ] || { echo "$NAME: no libheadplan.so in $d" >&2; exit 66; }
done
here=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# The generated header (hp_version.h) from a build folder: B's or A's when either is one,
# else this tree's build/.
inc=(-I "$here/include")
for d in "$B" "$A" "$here/build"; do
  if [ -e "$d/include/headplan/hp_version.h" ]; then inc+=(-I "$d/include"); break; fi
done
[ "${#inc[@]}" -eq 4 ] || { echo "$NAME: no include/headplan/hp_version.h in $B, $A or $here/build (a configured build folder)" >&2; exit 66; }
cc -O2 -std=c11 "${inc[@]}" "$here/bench/plan_count.c" \
  -o "$tmp/count" -L "$A" -lheadplan -lm
scene="$here/scenarios/default.yaml"
run() { LD_LIBRARY_PATH=$1 "$tmp/count" "$scene" "${@:2}"; }
