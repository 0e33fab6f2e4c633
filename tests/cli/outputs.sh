# Every subcommand checks its writes (issue 9): with stdout on a full device (/dev/full) or
# closed (>&-), and a file output past a file-size limit, the exit status is 74 with one line
# on stderr naming what could not be written, never 0 with cut output.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"
M="--c1 1.1e4 --c2 2.2e4"
mkdir -p "$TMP/bench" "$TMP/bench2"
cmds=(
  "--version"
  "--help"
  "solve $S/default.yaml"
  "solve $S/default.yaml --json"
  "analyze $S/default.yaml"
  "analyze $S/default.yaml --json"
  "ik --Ri 27 --Ro 30 --ri 30 $M"
  "fk --Ri 27 --Ro 30 --pressure 1000 $M --json"
  "paper $S/paper_expansion.yaml"
  "paper $S/paper_expansion.yaml --json"
  "batch $S/default.yaml --no-progress --format csv"
  "batch $S/default.yaml --no-progress --format jsonl -o -"
  "horizon $S/horizon/step.yaml --mode greedy"
  "horizon $S/horizon/step.yaml --mode greedy --json"
  "render $S/default.yaml --dry-run"
  "plot $TMP/result.csv --dry-run"
  "fit material $HP_SRC/examples/calibration/material_ri.csv --Ri-mm 27 --Ro-mm 30"
  "fit material $HP_SRC/examples/calibration/material_ri.csv --Ri-mm 27 --Ro-mm 30 --json"
)
"$HP_BIN" batch "$S/default.yaml" --no-progress --format csv -o "$TMP/result.csv" 2>/dev/null ||
  bad "setup: batch result"
# The benchmark lab beside the product checks its output the same way.
BENCH_BIN="$(dirname "$HP_BIN")/headplan-bench"
[ -x "$BENCH_BIN" ] && cmds+=("@bench --quick --only ik --out $TMP/bench --seed 7")
for c in "${cmds[@]}"; do
  bin="$HP_BIN"
  case "$c" in @bench*) bin="$BENCH_BIN"; c="${c#@bench }";; esac
  read -r -a argv <<<"$c"
  name="${argv[0]}"
  # Full device: the writes fail with ENOSPC.
  "$bin" "${argv[@]}" >/dev/full 2>"$TMP/err"; rc=$?
  expect_exit 74 "$c >/dev/full"
  expect_stderr_has "cannot write standard output: No space left on device" "$c >/dev/full"
  [ "$(grep -c 'cannot write' "$TMP/err")" -eq 1 ] && ok || bad "$c >/dev/full: not one line"
  # Closed stdout: the writes fail with EBADF (and no file the command opens takes fd 1).
  "$bin" "${argv[@]}" >&- 2>"$TMP/err"; rc=$?
  expect_exit 74 "$c >&-"
  expect_stderr_has "cannot write standard output" "$c >&-"
done

# A file output past the file-size limit (SIGXFSZ ignored, so the write fails with EFBIG):
# exit 74, one line naming the file asked for, and neither it nor its temporary file left.
# past_limit BLOCKS OUT LABEL ARGS...: runs headplan ARGS under `ulimit -f BLOCKS`.
# (stderr goes through a pipe: the limit would cut a file holding it too)
past_limit() {
  local blocks=$1 out=$2 label=$3; shift 3
  ( ulimit -f "$blocks"; trap '' XFSZ; exec "$HP_BIN" "$@" ) 2>&1 >/dev/null | cat >"$TMP/err"
  rc=${PIPESTATUS[0]}
  expect_exit 74 "$label past the size limit"
  expect_stderr_has "cannot write $out: File too large" "$label past the size limit named"
  [ "$(wc -l <"$TMP/err")" -eq 1 ] && ok || bad "$label past the size limit: not one line"
  [ ! -e "$out" ] && ! ls "$(dirname "$out")" | grep -qF "$(basename "$out").partial" && ok \
    || bad "a failed $label left a file"
}
past_limit 8 "$TMP/big.csv" "batch -o" batch "$S/default.yaml" --no-progress -o "$TMP/big.csv"
past_limit 8 "$TMP/hbig.csv" "horizon -o" horizon "$S/horizon/step.yaml" --mode greedy \
  -o "$TMP/hbig.csv"
# fit material --plot: an SVG headplan writes itself.
past_limit 1 "$TMP/chart.svg" "fit --plot" fit material \
  "$HP_SRC/examples/calibration/material_ri.csv" --Ri-mm 27 --Ro-mm 30 --plot "$TMP/chart.svg"
( ulimit -f 1; trap '' XFSZ
  exec "$BENCH_BIN" --quick --only ik --out "$TMP/bench2" --seed 7 ) 2>&1 >/dev/null | cat >"$TMP/err"
rc=${PIPESTATUS[0]}
expect_exit 74 "bench files past the size limit"
expect_stderr_has "cannot write" "bench file named"
finish
