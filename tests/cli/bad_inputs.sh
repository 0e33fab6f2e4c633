# The bad-input catalogue of the command line: runs every case of tests/cli/bad_inputs.txt
# and asserts, for each, the exact exit status, the message on stderr, the stdout rule, the
# number of stderr lines, and that the program did not die by a signal (status < 128).
#   bash tests/cli/bad_inputs.sh HEADPLAN_BIN SOURCE_DIR
# With BAD_INPUTS_REPORT=FILE it also writes one line per case, "N<TAB>status<TAB>stderr
# line 1", which scripts/bad_inputs_table.sh turns into the table of docs/bad-inputs.md.
source "$2/tests/cli_lib.sh"
CATALOGUE="$HP_SRC/tests/cli/bad_inputs.txt"
S="$HP_SRC/scenarios"
B="$HP_SRC/tests/scenes_bad"
T="$TMP/bad"
mkdir -p "$T"
export LC_ALL=C

# ---- small bad files, made here so that the catalogue needs no binary fixtures ----
HDR='t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg'
printf '%s\n0,0,0,0,0,0,0\n0.1,0,0' "$HDR" >"$T/truncated.csv"          # no final newline
printf '%s\n0,0,0,0,0,0,nan\n' "$HDR" >"$T/nan.csv"
printf '%s\n0,0,0,0,0,0,1e999\n' "$HDR" >"$T/overflow.csv"
printf '%s\n0,0,0,0,0,0\n' "$HDR" >"$T/six_fields.csv"
printf '%s\n0,0,0,0,0,0,0,0\n' "$HDR" >"$T/eight_fields.csv"
printf '%s\n0,0,0,0,0,0,0x10\n' "$HDR" >"$T/hex.csv"
printf 't,x,y,z,pitch,roll,yaw\n0,0,0,0,0,0,0\n' >"$T/wrong_header.csv"
printf '# rows: upside-down\n%s\n0,0,0,0,0,0,0\n' "$HDR" >"$T/bad_rows_comment.csv"
printf '\x7fELF\x02\x01\x01\x00\x00\x00garbage\n' >"$T/garbage.csv"     # binary, has NUL
printf '\xff\xfe\xfd\xfc\n\x80\x81\n' >"$T/garbage_nonul.csv"           # binary, no NUL
: >"$T/empty.csv"
printf '# only a comment\n\n' >"$T/comment_only.csv"
{ echo "$HDR"; printf '0,0,0,0,0,0,'; head -c 5000 /dev/zero | tr '\0' '0'; echo; } \
  >"$T/huge_line.csv"
printf '%s\r\n0,0.1,0,0,0,0,0\r\n0.1,0.1,0,0,0,zero,0\r\n' "$HDR" >"$T/crlf.csv"
printf '{"t_s":0,"x_mm":0,"y_mm":0,"z_mm":0,"pitch_deg":0,"roll_deg":0,"yaw_deg":0,"x_mm":1}\n' \
  >"$T/duplicate_key.jsonl"
printf '{"t_s":0,"x_mm":0,"y_mm":0,"z_mm":0,"pitch_deg":0,"roll_deg":0}\n' >"$T/missing_key.jsonl"
printf '{"t_s":0,"x_mm":"1","y_mm":0,"z_mm":0,"pitch_deg":0,"roll_deg":0,"yaw_deg":0}\n' \
  >"$T/string_value.jsonl"
printf '{"t_s":0,"x_mm":0,"y_mm":0,"z_mm":0,"pitch_deg":0,"roll_deg":0,"yaw_deg":0,"w":1}\n' \
  >"$T/unknown_key.jsonl"
printf '[0,0,0,0,0,0,0]\n' >"$T/not_object.jsonl"
printf '{"t_s":0,"x_mm":0,\n' >"$T/broken.jsonl"
mkdir -p "$T/dir.csv" "$T/dir.yaml" "$T/outdir"
# Rows kind, directive and output-safety cases (issue 9).
DIR='# headplan-trace: rows=deviation'
printf '%s\n0,0.1,0,0,0,0,0\n' "$HDR" >"$T/no_kind.csv"
printf '%s\n%s\n0,0.1,0,0,0,0,0\n' "$DIR" "$HDR" >"$T/deviation.csv"
printf '# Rows: deviation\n%s\n0,0.1,0,0,0,0,0\n' "$HDR" >"$T/rows_capital.csv"
printf '%s\n0,0.1,0,0,0,0,0\n%s\n0.1,0,0,0,0,0,0\n' "$HDR" "$DIR" >"$T/late_directive.csv"
printf '{"rows": "deviation"}\n{"t_s":0,"x_mm":0,"y_mm":0,"z_mm":0,"pitch_deg":0,"roll_deg":0,"yaw_deg":0}\n' \
  >"$T/old_header.jsonl"
printf '%s\n0,\xc3\x28,0,0,0,0,0\n0,0,0,0,0,0,0\n' "$HDR" >"$T/bad_utf8.csv"
printf '%s\n0,0,0,0,0\x00,0,0\n0,0,0,0,0,0,0\n' "$HDR" >"$T/nul_row.csv"
printf '%s\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n0,0,0,0,1,0.1,0,0\n' "$DIR" >"$T/quat_norm.csv"
ln -sf "$T/outlink_target.csv" "$T/outlink.csv"
mkfifo "$T/outfifo.csv"
# Calibration data (headplan fit).
cp "$HP_SRC/examples/calibration/layout_rows.csv" "$T/rows.csv"
cp "$HP_SRC/examples/calibration/material_ri.csv" "$T/mat.csv"
# Scenes with a NUL byte or broken UTF-8 on line 6 (reported there, not at 1:1).
{ head -n 5 "$S/default.yaml"; printf 'name: ab\x00cd\n'; tail -n +7 "$S/default.yaml"; } >"$T/nul.yaml"
{ head -n 5 "$S/default.yaml"; printf 'notes: ab\xffcd\n'; tail -n +6 "$S/default.yaml"; } >"$T/bad_utf8.yaml"
# Layout scenes derived from the default one.
sed 's/^correction:.*/correction: {x_mm: 5000, y_mm: 0, z_mm: 0, pitch_deg: 0, roll_deg: 0, yaw_deg: 0}/' \
  "$S/default.yaml" >"$T/correction_too_far.yaml"
sed '/^correction:/d; /^trace:/d' "$S/default.yaml" >"$T/no_correction.yaml"
sed 's#^trace:.*#trace: {file: missing_trace.csv, rows: deviation}#' "$S/default.yaml" \
  >"$T/trace_missing.yaml"
sed 's/max_iter: [0-9]*/max_iter: 1/' "$S/saturation.yaml" >"$T/one_iteration.yaml"
head -c 200 "$S/default.yaml" >"$T/truncated.yaml"
sed 's/^  shape: ellipsoid/  shape: cube/; s/$/\r/' "$S/default.yaml" >"$T/crlf_bad_shape.yaml"
# Batch results (headplan plot): the default scene's first three planned rows, then one
# number beyond 1e300 in magnitude (an error, a pressure) or a line number of 1e15.
"$HP_BIN" batch "$S/default.yaml" --format csv --no-progress --no-times -o "$T/result_all.csv" \
  2>/dev/null
edit_result() { # edit_result COLUMN VALUE OUT: the first row's COLUMN set to VALUE
  awk -F, -v OFS=, -v c="$1" -v v="$2" '
    /^#/ { print; next }
    !h { h = 1; for (i = 1; i <= NF; ++i) if ($i == c) k = i; print; next }
    { if (++r == 1) $k = v; if (r <= 3) print }' "$T/result_all.csv" >"$3"
}
edit_result error_x_mm 1e301 "$T/huge_error.csv"
edit_result side_chin_left_pressure_pa -1e301 "$T/huge_pressure.csv"
edit_result line 1e15 "$T/huge_line_number.csv"

# ---- the catalogue ----
report=${BAD_INPUTS_REPORT:-}
[ -z "$report" ] || : >"$report"
n=0
while IFS= read -r line || [ -n "$line" ]; do
  case $line in '#'*|'') continue;; esac
  n=$((n+1))
  IFS='|' read -r want flags args msg <<<"$line"
  want=$(echo $want); flags=$(echo $flags)
  msg="${msg#" "}"
  msg=${msg//'$S'/$S}; msg=${msg//'$T'/$T}; msg=${msg//'$B'/$B}
  # Arguments: split on blanks; '' stands for an empty argument.
  argv=()
  for a in $args; do
    a=${a//'$S'/$S}; a=${a//'$T'/$T}; a=${a//'$B'/$B}
    [ "$a" = "''" ] && a=""
    argv+=("$a")
  done
  label="case $n (${argv[*]:0:3}...)"
  run "${argv[@]}"
  [ -z "$report" ] || printf '%s\t%s\t%s\n' "$n" "$rc" "$(head -n 1 "$TMP/err")" >>"$report"
  [ "$rc" -lt 128 ] && ok || bad "$label: died with status $rc (signal?)"
  expect_exit "$want" "$label"
  expect_stderr_has "$msg" "$label"
  lines=1; allow_out=0
  for f in ${flags//,/ }; do
    case $f in
      -) ;;
      out) allow_out=1 ;;
      lines=*) lines=${f#lines=} ;;
      *) bad "$label: unknown flag '$f' in the catalogue" ;;
    esac
  done
  [ "$allow_out" = 1 ] || expect_stdout_empty "$label"
  got=$(wc -l <"$TMP/err")
  [ "$got" -eq "$lines" ] && ok || bad "$label: $got lines on stderr, want $lines"
  # The message is the first line (batch: the first bad row precedes the summary).
  head -n 1 "$TMP/err" | grep -qF -- "$msg" && ok || bad "$label: message not on line 1"
done <"$CATALOGUE"
[ "$n" -ge 60 ] && ok || bad "catalogue has only $n cases"
echo "bad_inputs: $n cases"
finish
