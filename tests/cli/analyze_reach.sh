# headplan analyze and headplan solve agree (issue 16): on every layout scene of the
# catalogue, the reach analyze reports along each commanded axis is where solve stops
# answering `reached`: solve at 99 % of it exits 0 (reached), at 101 % exits 1 (closest: a
# limit binds). An axis analyze reports as not commanded (null) has no reach: solve of a
# correction along it exits 2 (uncommanded), never 0. Reaches at the search cap (50 mm,
# 30 deg: "at least") are skipped. 1 % is far above the bisection's resolution (~1e-15 of
# the cap) and far below any reach here (> 0.5 mm), so each side lies clearly on its side.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"
scenes=0
for f in "$S"/*.yaml; do
    run analyze "$f" --json
    if [ "$rc" -eq 65 ] && grep -qF "needs a layout scene" "$TMP/err"; then continue; fi
    expect_exit 0 "analyze $(basename "$f")"
    scenes=$((scenes+1))
    python3 - "$TMP/out" > "$TMP/cases" <<'PY' || bad "$(basename "$f"): reach cases"
import json, sys
d = json.load(open(sys.argv[1]))
for i, k in enumerate(["x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"]):
    c = [0.0] * 6
    if d["reach"][k] is None:
        c[i] = 1.0
        print(2, ",".join(repr(x) for x in c), d["level"])
        continue
    for r in d["reach"][k]:
        if abs(r) >= (50 if i < 3 else 30): continue
        assert abs(r) > 0.05, (k, r)
        for f, want in ((0.99, 0), (1.01, 1)):
            c[i] = f * r
            print(want, ",".join(repr(x) for x in c), d["level"])
PY
    [ -s "$TMP/cases" ] || bad "$(basename "$f"): no reach cases"
    while read -r want corr level; do
        run solve "$f" --level "$level" --correction "$corr"
        expect_exit "$want" "$(basename "$f"): solve at $corr (level $level)"
    done < "$TMP/cases"
done
[ "$scenes" -ge 11 ] && ok || bad "only $scenes layout scenes analysed"
finish
