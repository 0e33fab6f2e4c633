#!/usr/bin/env bash
# headplan paper: the paper's two tables, computed numbers and the DIFFERS marks.
# Reference numbers: docs/model.md section 3 (closed form, confirmed by quadrature of both
# integrals): expansion ro 32.49649 mm, P 3053.1854 Pa; compression ri 23 mm,
# ro 28.66033 mm, P -5402.1338 Pa.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"

run paper
expect_exit 0 "default tables"
expect_stdout_has "== Volumetric Deformation (Expansion)" "expansion title"
expect_stdout_has "== Volumetric Deformation (Compression)" "compression title"
expect_stdout_has "ro [mm] (volume law)   32.49649       .033 m     DIFFERS: the volume law gives 32.49649 mm" "expansion ro"
expect_stdout_has "P [Pa] (closed form)   3053.1854      .76        DIFFERS: the closed form gives 3053.1854 Pa; .76 matches it in no unit" "expansion P"
expect_stdout_has "ri [mm] (input)        23.00000       .03 m      DIFFERS: this study uses ri = 23.00000 mm; the printed ri gives ro = 33.72998 mm" "compression ri errata"
expect_stdout_has "ro [mm] (volume law)   28.66033       .028 m     DIFFERS" "compression ro"
expect_stdout_has "P [Pa] (closed form)   -5402.1338     -.34       DIFFERS" "compression P"
expect_stdout_has "ri [mm] (input)        30.00000       .03 m      agrees" "expansion ri agrees"
expect_stdout_has "Ri [mm]                25.00000       .025 m     agrees" "compression Ri agrees"
# quadrature of both integrals agrees with the closed form to the printed 4 decimals
[ "$(grep -c '^Gauss-Legendre 20 pts, P(.) form *3053.1854 ' "$TMP/out")" -eq 2 ] && ok || bad "gauss expansion"
[ "$(grep -c '^adaptive Gauss-Kronrod, P(.) form *-5402.1338 ' "$TMP/out")" -eq 2 ] && ok || bad "adaptive compression"
# dV approx 0 in both tables
[ "$(grep -c '^dV \[m^3\] .* agrees (printed as approx. 0' "$TMP/out")" -eq 2 ] && ok || bad "dV"
[ "$(grep -c 'DIFFERS' "$TMP/out")" -eq 5 ] && ok || bad "five DIFFERS marks (ro, P; ri, ro, P)"
[ ! -s "$TMP/err" ] && ok || bad "stderr not empty"
cp "$TMP/out" "$TMP/builtin"

# the built-in copies give the same tables as the scenario files
run paper "$S/paper_expansion.yaml" "$S/paper_compression.yaml"
expect_exit 0 "files"
grep -v '^scene: ' "$TMP/out" > "$TMP/a"; grep -v '^scene: ' "$TMP/builtin" > "$TMP/b"
cmp -s "$TMP/a" "$TMP/b" && ok || bad "built-in scenes differ from scenarios/paper_*.yaml"

# JSON: full-precision numbers, within half a unit of the last digit docs/model.md gives
run paper --json
expect_exit 0 "json"
python3 - "$TMP/out" <<'PY' && ok || bad "json values"
import json, sys
t = json.load(open(sys.argv[1]))["tables"]
e, c = t[0], t[1]
def close(a, b, tol): assert abs(a - b) <= tol, (a, b)
close(e["computed"]["ro_m"], 0.03249649, 0.5e-8)
close(e["computed"]["pressure_pa"], 3053.1854, 0.5e-4)
close(c["inputs"]["ri_m"], 0.023, 1e-17)
close(c["computed"]["ro_m"], 0.02866033, 0.5e-8)
close(c["computed"]["pressure_pa"], -5402.1338, 0.5e-4)
for tab in t:
    for q in tab["quadrature"]:
        assert q["rel_diff"] < 1e-12, q    # quadrature to near machine precision
    assert tab["printed"]["pressure_pa"]["agrees"] is False
    assert tab["printed"]["ro_m"]["check"].startswith("DIFFERS")
    assert tab["printed"]["C1_pa"]["agrees"] is True
assert c["printed"]["ri_m"]["agrees"] is False and e["printed"]["ri_m"]["agrees"] is True
PY

# errors: one line on stderr, nothing on stdout
run paper "$S/default.yaml"
expect_exit 65 "layout scene"
expect_stdout_empty "layout scene"
expect_stderr_has "not a single-bladder scene" "layout scene"
run paper "$S/no_such.yaml"
expect_exit 66 "missing file"
expect_stderr_has "no_such.yaml: cannot open" "missing file"
run paper "$HP_SRC/tests/scenes_bad/number_nan.yaml"
expect_exit 65 "bad scene"
expect_stderr_has "number_nan.yaml:6:10: bladder_defaults.Ro_mm: '.nan' is not a finite number" "bad scene"
expect_stdout_empty "bad scene"
run paper --bogus
expect_exit 64 "unknown option"
expect_stderr_has "--bogus: unknown option" "unknown option"
run paper --help
expect_exit 0 "help"
expect_stdout_has "usage: headplan paper" "help"
finish
