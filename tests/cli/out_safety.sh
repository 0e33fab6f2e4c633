# Every option that names a file to write (batch -o, horizon -o, plot -o and --script-out,
# render -o and --script-out, fit layout -o) refuses, with exit 73, one line on stderr and
# nothing written: each of the command's inputs (by its own name and through a hard link),
# a device, a FIFO and a symbolic link. After each refusal the input is byte-identical, the
# device is still a device, and no temporary file is left beside any of them. A last run per
# command shows the same option writes an ordinary new file.
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"
W="$TMP/w"; mkdir -p "$W"; cd "$W" || exit 1
export LC_ALL=C

# Copies of the inputs, so that a failure of this test cannot damage the source tree.
sed "s#file: traces/#file: $S/traces/#" "$S/default.yaml" >scene.yaml
cp "$S/horizon/step.yaml" hscene.yaml
sed -i "s#file: ../traces/#file: $S/traces/#" hscene.yaml
{ echo '# headplan-trace: rows=deviation'; sed -n '/^t_s/,$p' "$S/traces/step.csv" | head -41; } >trace.csv
"$HP_BIN" batch scene.yaml trace.csv --no-progress --no-times -o result.csv 2>/dev/null ||
  { echo "setup: batch failed"; exit 1; }
"$HP_BIN" fit layout --help >/dev/null 2>&1 && have_fit=1 || have_fit=0
mkfifo fifo.csv
ln -s result.csv link.csv
for f in scene.yaml hscene.yaml trace.csv result.csv; do cp "$f" "$f.orig"; ln "$f" "hard_$f"; done
have_gnuplot=0; command -v gnuplot >/dev/null && have_gnuplot=1

# refuse NAME TARGET CMD...: CMD (with TARGET in it) must exit 73 with one line, naming TARGET.
refuse() {
  local name=$1 target=$2; shift 2
  run "$@"
  expect_exit 73 "$name -> $target"
  [ "$(wc -l <"$TMP/err")" -eq 1 ] && ok || bad "$name -> $target: stderr not one line"
  expect_stderr_has "$target" "$name -> $target named"
  for f in scene.yaml hscene.yaml trace.csv result.csv; do
    cmp -s "$f" "$f.orig" && ok || bad "$name -> $target: $f changed"
  done
  [ -c /dev/null ] && [ -p fifo.csv ] && [ -L link.csv ] && ok || bad "$name -> $target: a special file was replaced"
  ls ./*partial* >/dev/null 2>&1 && bad "$name -> $target: a temporary file was left" || ok
}

for t in trace.csv hard_trace.csv hscene.yaml hard_hscene.yaml /dev/null fifo.csv link.csv; do
  refuse "horizon -o" "$t" horizon hscene.yaml trace.csv --mode greedy -o "$t"
done
for t in trace.csv hard_trace.csv scene.yaml hard_scene.yaml /dev/null fifo.csv link.csv; do
  refuse "batch -o" "$t" batch scene.yaml trace.csv --no-progress --format csv -o "$t"
done
# plot and render check their pictures' names (.png, .svg) before anything else, so a
# picture cannot name a CSV or YAML input; the kept script can, and both are checked.
for t in result.csv hard_result.csv scene.yaml trace.csv /dev/null fifo.csv link.csv; do
  refuse "plot --script-out" "$t" plot result.csv --scene scene.yaml --trace trace.csv \
    --dry-run --script-out "$t"
done
for t in scene.yaml hard_scene.yaml /dev/null fifo.csv link.csv; do
  refuse "render --script-out" "$t" render scene.yaml --dry-run --script-out "$t"
done
cp result.csv result.png; cp result.png result.png.orig
ln -s result.png link.png; mkfifo fifo.png
# (Without gnuplot these stop earlier, with 69: the picture is drawn by gnuplot.)
if [ "$have_gnuplot" = 1 ]; then
  for t in result.png link.png fifo.png; do
    refuse "plot -o" "$t" plot result.png -o "$t" --script-out s.gp
    cmp -s result.png result.png.orig && ok || bad "plot -o $t: result.png changed"
    [ -e s.gp ] && bad "plot -o $t: the script was written although the picture was refused" || ok
  done
fi
if [ "$have_fit" = 1 ]; then
  for t in scene.yaml hard_scene.yaml; do
    run fit layout scene.yaml result.csv -o "$t"
    [ "$rc" -ne 0 ] && ok || bad "fit layout -o $t: exit 0"
    cmp -s scene.yaml scene.yaml.orig && ok || bad "fit layout -o $t: scene changed"
  done
fi

# fit: the material chart (--plot, an SVG written by headplan) and the layout chart's kept
# script (--plot-script) are checked like every other output.
cp "$HP_SRC/examples/calibration/material_ri.csv" mdata.csv; cp mdata.csv mdata.csv.orig
cp mdata.csv mdata.svg; cp mdata.svg mdata.svg.orig; ln -s mdata.csv mlink.svg
for t in mdata.svg mlink.svg; do
  refuse "fit material --plot" "$t" fit material mdata.svg --Ri-mm 27 --Ro-mm 30 --plot "$t"
  cmp -s mdata.svg mdata.svg.orig && cmp -s mdata.csv mdata.csv.orig && ok || bad "fit --plot $t: data changed"
done
cp "$HP_SRC/examples/calibration/layout_rows.csv" ldata.csv; cp ldata.csv ldata.csv.orig
if [ "$have_gnuplot" = 1 ]; then
  for t in ldata.csv scene.yaml fifo.csv link.csv; do
    refuse "fit layout --plot-script" "$t" fit layout scene.yaml ldata.csv --plot lp.png --plot-script "$t"
    cmp -s ldata.csv ldata.csv.orig && ok || bad "fit layout --plot-script $t: data changed"
  done
fi

# The same options write an ordinary new file.
run horizon hscene.yaml trace.csv --mode greedy -o new_h.csv
expect_exit 0 "horizon -o new file"; [ -s new_h.csv ] && ok || bad "horizon -o wrote nothing"
run plot result.csv --dry-run --script-out new.gp
expect_exit 0 "plot --script-out new file"; grep -q "set output" new.gp && ok || bad "plot script"
if [ "$have_gnuplot" = 1 ]; then
  run render scene.yaml -o new.png --script-out new_r.gp
  expect_exit 0 "render -o new file"; [ -s new.png ] && [ -s new_r.gp ] && ok || bad "render files"
  # The kept script names the final picture, not the temporary one it was drawn to.
  grep -q 'set output "./new.png"' new_r.gp && ok || bad "render script names $(grep 'set output' new_r.gp)"
fi
ls ./*partial* >/dev/null 2>&1 && bad "a temporary file was left" || ok
finish
