# headplan ik / fk: docs/model.md §3 reference values, every bad-input class, fk round trip.
source "$2/tests/cli_lib.sh"

# jnum FMT KEY: the number under KEY (a.b for nested) in the JSON on stdout, in format FMT.
# The reference table prints ro to 5 decimals and P to 4: compare at those digits.
jnum() { python3 -c 'import json,sys; v=json.load(open(sys.argv[1])); 
for k in sys.argv[3].split("."): v=v[k]
print(format(v, sys.argv[2]))' "$TMP/out" "$1" "$2"; }
expect_json() { # FORMAT KEY WANT WHAT
  got=$(jnum "$1" "$2" 2>/dev/null); [ "$got" = "$3" ] && ok || bad "$4: $2 = '$got', want '$3'"; }

M="--c1 1.1e4 --c2 2.2e4"
# --- reference rows (C1 = 1.1e4 Pa, C2 = 2.2e4 Pa) ---
run ik --Ri 27 --Ro 30 --ri 30 $M --json
expect_exit 0 "ik row 1"
expect_json .5f ro_mm 32.49649 "ik row 1"
expect_json .4f pressure_pa 3053.1854 "ik row 1"
expect_json .10f lambda_i 1.1111111111 "ik row 1"
for k in ri_mm ro_mm pressure_pa lambda_i lambda_o c1_pa c2_pa Ri_mm Ro_mm dP_dri_pa_per_mm; do
  expect_stdout_has "\"$k\":" "ik json key $k"; done
expect_stdout_has '"limit_point": null' "ik row 1 no limit point"
run ik --Ri 25 --Ro 30 --ri 23 $M --json
expect_exit 0 "ik row 2"
expect_json .5f ro_mm 28.66033 "ik row 2"
expect_json .4f pressure_pa -5402.1338 "ik row 2"
run ik --Ri 27.5 --Ro 30 --ri 27.5 $M --json
expect_exit 0 "ik row 3"
expect_json .5f ro_mm 30.00000 "ik row 3"
expect_json .4f pressure_pa 0.0000 "ik row 3"
# the same in the finite-element convention (C10 = C1/2, C01 = C2/2) and as a table
run ik --Ri 27 --Ro 30 --ri 30 --c10 5.5e3 --c01 1.1e4 --json
expect_json .4f pressure_pa 3053.1854 "ik fe convention"
expect_json .1f c1_pa 11000.0 "ik fe convention reports paper C1"
run ik --Ri=27 --Ro=30 --ri=30 --c1=1.1e4 --c2=2.2e4
expect_exit 0 "ik table"
expect_stdout_has "3053.185409" "ik table pressure"
expect_stdout_has "32.49648877" "ik table ro"
run ik --help
expect_exit 0 "ik --help"; expect_stdout_has "usage: headplan ik" "ik --help"
run fk --help
expect_exit 0 "fk --help"; expect_stdout_has "usage: headplan fk" "fk --help"

# --- fk round trip: the printed pressure back to the radius ---
run fk --Ri 27 --Ro 30 --pressure 3053.1854090727388 $M --json
expect_exit 0 "fk row 1"
expect_json .9f ri_mm 30.000000000 "fk round trip row 1"
run fk --Ri 25 --Ro 30 --pressure -5402.1338 $M --json
expect_exit 0 "fk row 2"
expect_json .5f ri_mm 23.00000 "fk round trip row 2"
run fk --Ri 27 --Ro 30 --pressure 0 $M --json
expect_json .12f ri_mm 27.000000000000 "fk zero pressure"
# neo-Hookean 27/30 mm shell: limit point at lambda_i 1.4312271769565827 (quad), P there
# 1434.699186 Pa; below it fk works and reports it, at and above it exit 65
run fk --Ri 27 --Ro 30 --pressure 1000 --c1 1.1e4 --c2 0 --json
expect_exit 0 "fk below limit"
expect_json .9f limit_point.lambda_i 1.431227177 "fk limit point"
expect_json .3f limit_point.pressure_pa 1434.699 "fk limit pressure"
run fk --Ri 27 --Ro 30 --pressure 1500 --c1 1.1e4 --c2 0
expect_exit 65 "fk above limit"; expect_stdout_empty "fk above limit"
expect_stderr_has "limit-point pressure 1434.69918" "fk above limit"
expect_stderr_has "--pressure" "fk above limit names option"

# --- usage errors: exit 64, stderr names the option, stdout empty ---
usage() { # WHAT WANT_STDERR ARGS...
  local what=$1 want=$2; shift 2; run "$@"
  expect_exit 64 "$what"; expect_stdout_empty "$what"; expect_stderr_has "$want" "$what"; }
usage "unknown option" "'--bogus'" ik --Ri 27 --Ro 30 --ri 30 $M --bogus
usage "missing --Ri" "--Ri: missing" ik --Ro 30 --ri 30 $M
usage "missing --Ro" "--Ro: missing" fk --Ri 27 --pressure 1 $M
usage "missing --ri" "--ri: missing" ik --Ri 27 --Ro 30 $M
usage "missing --pressure" "--pressure: missing" fk --Ri 27 --Ro 30 $M
usage "missing --c2" "--c2: missing" ik --Ri 27 --Ro 30 --ri 30 --c1 1
usage "missing --c01" "--c01: missing" ik --Ri 27 --Ro 30 --ri 30 --c10 1
usage "missing moduli" "--c1: missing" ik --Ri 27 --Ro 30 --ri 30
usage "mixed conventions" "cannot mix" ik --Ri 27 --Ro 30 --ri 30 --c1 1 --c2 1 --c10 1
usage "mixed conventions 2" "--c01" fk --Ri 27 --Ro 30 --pressure 1 --c1 1 --c01 1
usage "missing value" "--ri: missing value" ik --Ri 27 --Ro 30 $M --ri
usage "repeated option" "--Ri: given more than once" ik --Ri 27 --Ri 28 --Ro 30 --ri 30 $M
usage "not a number" "--ri: 'abc' is not a number" ik --Ri 27 --Ro 30 --ri abc $M
usage "nan" "--Ro: 'nan'" ik --Ri 27 --Ro nan --ri 30 $M
usage "inf" "--pressure: 'inf'" fk --Ri 27 --Ro 30 --pressure inf $M
usage "trailing junk" "--c1: '1e4x'" ik --Ri 27 --Ro 30 --ri 30 --c1 1e4x --c2 0
usage "overflow" "--c2: '1e999'" ik --Ri 27 --Ro 30 --ri 30 --c1 1 --c2 1e999

# --- bad data: exit 65 ---
data() { local what=$1 want=$2; shift 2; run "$@"
  expect_exit 65 "$what"; expect_stdout_empty "$what"; expect_stderr_has "$want" "$what"; }
data "ri zero" "--ri: must be > 0" ik --Ri 27 --Ro 30 --ri 0 $M
data "ri negative" "--ri: must be > 0" ik --Ri 27 --Ro 30 --ri -3 $M
data "Ri negative" "--Ri: must be > 0" ik --Ri -27 --Ro 30 --ri 30 $M
data "Ri = Ro" "--Ro: must be greater than --Ri" ik --Ri 30 --Ro 30 --ri 30 $M
data "Ri > Ro" "--Ro: must be greater than --Ri" fk --Ri 31 --Ro 30 --pressure 1 $M
data "c1 zero" "--c1: must be > 0" ik --Ri 27 --Ro 30 --ri 30 --c1 0 --c2 1
data "c1 negative" "--c1: must be > 0" fk --Ri 27 --Ro 30 --pressure 1 --c1 -1 --c2 1
data "c2 negative" "--c2: must be >= 0" ik --Ri 27 --Ro 30 --ri 30 --c1 1 --c2 -1
data "c10 negative" "--c10: must be > 0" ik --Ri 27 --Ro 30 --ri 30 --c10 -1 --c01 1
data "c01 negative" "--c01: must be >= 0" ik --Ri 27 --Ro 30 --ri 30 --c10 1 --c01 -1
data "Ri tiny vs Ro" "Ri" ik --Ri 1e-12 --Ro 30 --ri 30 $M
data "ri out of range" "--ri" ik --Ri 27 --Ro 30 --ri 1e-300 $M
data "pressure out of range" "--pressure" fk --Ri 27 --Ro 30 --pressure -1e300 $M
finish
