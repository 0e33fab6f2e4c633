# Sourced by bench/plan_ab.sh and bench/plan_bits.sh (NAME A B set): checks that folders A
# and B hold a libheadplan.so, compiles bench/plan_count.c once against this tree's headers
# into $tmp/count (tmp removed on exit), and defines run LIBDIR ARGS... (headplan-bench-count
# on the default scene against that folder's library).
for d in "$A" "$B"; do
  [ -e "$d/libheadplan.so" ] || { echo "$NAME: no libheadplan.so in $d" >&2; exit 66; }
done
here=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cc -O2 -std=c11 -I "$here/include" -I "$here/build/include" "$here/bench/plan_count.c" \
  -o "$tmp/count" -L "$A" -lheadplan -lm
scene="$here/scenarios/default.yaml"
run() { LD_LIBRARY_PATH=$1 "$tmp/count" "$scene" "${@:2}"; }
