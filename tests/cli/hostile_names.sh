# Names and data never become gnuplot code. A catalogue of hostile strings (quotes,
# backslashes, newlines, '!', backquotes, system(), $(...), macros, control bytes, bytes that
# are not UTF-8) goes through every way a string reaches a drawing: the file names of
# headplan plot's RESULT, -o and --script-out, its result's column names and its --scene's
# name; headplan render's -o and scene name; fit layout --plot and --plot-script; fit
# material --plot; the benchmark lab's --out folder and catalogue scene names. Each payload
# would `touch CANARY` in the folder gnuplot runs in; CANARY must never appear, and each
# command either draws its picture (exit 0, a whole PNG/SVG) or refuses with its documented
# status and a message naming the option. Every kept script is also run by hand. Relative
# picture names that gnuplot opens its own way ('|...' a pipe, '~/...' in HOME), and text an
# SVG cannot hold ("]]>", U+FFFE, U+FFFF), have their own cases below.
source "$2/tests/cli_lib.sh"
export LC_ALL=C # [[:cntrl:]] below: bytes 0x01-0x1f and 0x7f
S="$HP_SRC/scenarios"
E="$HP_SRC/examples/calibration"
BENCH="$(dirname "$HP_BIN")/headplan-bench"
W="$TMP/w"
mkdir -p "$W"
cd "$W" || exit 1 # headplan's gnuplot runs here: a payload would touch ./CANARY

names=(
  "q'.system('touch CANARY').'"
  "bs\\'.system('touch CANARY').'\\"
  $'nl\n!touch CANARY\n'
  $'eod\nEOD\n!touch CANARY\nx'
  $'cr\r!touch CANARY\r'
  '`touch CANARY`'
  'sys system("touch CANARY")'
  'sh $(touch CANARY)'
  '!touch CANARY'
  '@GPVAL_TERM @ARGV'
  $'bytes\xff\xfe\xc3('
  $'tab\tdel\x7f'
  'trail\'
  "''.system('touch CANARY').''"
  "'lead {brace}"
)
# Under the sanitizers one payload of each kind (gnuplot quoting, a line break, gnuplot's
# EOD, a shell backquote, bytes that are not UTF-8), and the lab once: its five runs took half
# an hour there. The plain pass runs the whole catalogue.
kinds=(0 2 3 5 10) # the lab's runs in the plain pass too
picked=("${!names[@]}"); lab=("${kinds[@]}")
if under_sanitizers; then picked=("${kinds[@]}"); lab=(2); fi

has_ctl() { [[ $1 == *[[:cntrl:]]* ]]; }
magic() { head -c "$2" "$1" 2>/dev/null | od -An -tx1 | tr -d ' \n'; }
is_png() { [ "$(magic "$1" 8)" = 89504e470d0a1a0a ]; }
is_svg() { head -c 400 "$1" 2>/dev/null | grep -q '<svg'; }
# no_canary WHAT [FOLDER]: the payload did not run (in W, or FOLDER for the lab).
no_canary() {
  local d="${2:-$W}"
  if [ -e "$d/CANARY" ]; then bad "$1: a payload ran (CANARY created)"; rm -f "$d/CANARY"
  else ok; fi
}
# redraw WHAT SCRIPT: the kept script run by hand (as its header says) runs no payload.
redraw() {
  [ -f "$2" ] || { bad "$1: no kept script"; return; }
  gnuplot "$2" >/dev/null 2>&1
  no_canary "$1: the kept script redrawn by hand"
}
# drawn WHAT PICTURE png|svg [report]: exit 0, nothing on stdout (unless the command prints a
# report there) nor on stderr, a whole picture under its name.
drawn() {
  expect_exit 0 "$1"
  [ "$4" = report ] || expect_stdout_empty "$1"
  # nothing from gnuplot either (text it cannot convert from UTF-8 would warn there)
  [ ! -s "$TMP/err" ] && ok || bad "$1: stderr not empty"
  if [ "$3" = png ]; then is_png "$2" && ok || bad "$1: no PNG under its name"
  else is_svg "$2" && ok || bad "$1: no SVG under its name"; fi
}
# refused_name WHAT OPTION PICTURE: a picture name with a control character is refused (64)
# by name, and nothing is written.
refused_name() {
  expect_exit 64 "$1"
  expect_stderr_has "$2: " "$1"
  expect_stderr_has "control character" "$1"
  [ "$(wc -l <"$TMP/err")" -eq 1 ] && ok || bad "$1: message not one line"
  [ ! -e "$3" ] && ok || bad "$1: the picture was written"
}
# scene_named NAME SRC OUT: SRC with its name: replaced by NAME (a YAML double-quoted scalar;
# control characters as \x escapes, other bytes as they are).
scene_named() {
  python3 - "$1" "$2" "$3" <<'PY'
import os, sys
name, src, out = os.fsencode(sys.argv[1]), sys.argv[2], sys.argv[3]
q = b"".join(b"\\\\" if c == 0x5c else b'\\"' if c == 0x22 else
             b"\\x%02x" % c if c < 0x20 or c == 0x7f else bytes([c]) for c in name)
lines = open(src, "rb").read().split(b"\n")
lines = [b'name: "' + q + b'"' if l.startswith(b"name:") else l for l in lines]
open(out, "wb").write(b"\n".join(lines))
PY
}
# A result to draw, and a trace the hostile scenes can name by absolute path.
"$HP_BIN" batch "$S/nodding.yaml" -o "$W/r.csv" --no-progress --no-times 2>/dev/null ||
  bad "batch of the result to draw"

for i in "${picked[@]}"; do
  n="${names[$i]}"
  t="name $i"

  # plot: the result's file name (in the title)
  cp "$W/r.csv" "$W/$n.csv"
  run plot "$W/$n.csv" -o "$W/p$i.png" --size 400x300 --script-out "$W/p$i.gp"
  drawn "$t: plot RESULT" "$W/p$i.png" png
  no_canary "$t: plot RESULT"
  redraw "$t: plot RESULT --script-out" "$W/p$i.gp"

  # plot -o and --script-out
  run plot "$W/r.csv" -o "$W/$n.png" --size 400x300 --script-out "$W/$n.gp"
  if has_ctl "$n"; then refused_name "$t: plot -o" "-o" "$W/$n.png"
  else drawn "$t: plot -o" "$W/$n.png" png; redraw "$t: plot -o, kept" "$W/$n.gp"; fi
  no_canary "$t: plot -o"
  rm -f "$W/$n.png" "$W/$n.gp"

  # plot: a pressure column's name (a CSV field holds no line break or comma)
  if [[ $n != *[$'\n\r,']* ]]; then
    python3 - "$n" "$W/r.csv" "$W/c$i.csv" <<'PY'
import os, sys
name, src, out = os.fsencode(sys.argv[1]), sys.argv[2], sys.argv[3]
text = open(src, "rb").read().replace(b"base_neck_left_pressure_pa",
                                      name + b"_pressure_pa")
open(out, "wb").write(text)
PY
    run plot "$W/c$i.csv" -o "$W/c$i.png" --size 400x300 --script-out "$W/c$i.gp"
    drawn "$t: plot, column name" "$W/c$i.png" png
    no_canary "$t: plot, column name"
    redraw "$t: plot, column name, kept" "$W/c$i.gp"
  fi

  # render and plot --scene: the scene's name (the scene reader refuses control characters
  # and bytes that are not UTF-8: 65)
  scene_named "$n" "$S/nodding.yaml" "$W/s$i.yaml"
  sed -i "s|traces/nodding.csv|$S/traces/nodding.csv|" "$W/s$i.yaml"
  run render "$W/s$i.yaml" -o "$W/s$i.png" --size 400x300 --script-out "$W/s$i.gp"
  if has_ctl "$n" || ! printf '%s' "$n" | iconv -f UTF-8 -t UTF-8 >/dev/null 2>&1; then
    expect_exit 65 "$t: render, scene name"
    expect_stderr_has "s$i.yaml:4:" "$t: render, scene name (file:line:col)"
  else
    drawn "$t: render, scene name" "$W/s$i.png" png
    redraw "$t: render, scene name, kept" "$W/s$i.gp"
    "$HP_BIN" batch "$W/s$i.yaml" -o "$W/rs$i.csv" --no-progress --no-times 2>/dev/null ||
      bad "$t: batch of the hostile scene"
    run plot "$W/rs$i.csv" --scene "$W/s$i.yaml" -o "$W/ps$i.png" --size 400x300 \
        --script-out "$W/ps$i.gp"
    drawn "$t: plot --scene, scene name" "$W/ps$i.png" png
    redraw "$t: plot --scene, kept" "$W/ps$i.gp"
  fi
  no_canary "$t: render/plot, scene name"

  # render -o
  run render "$S/default.yaml" -o "$W/$n.svg" --size 400x300 --script-out "$W/$n.gp"
  if has_ctl "$n"; then refused_name "$t: render -o" "-o" "$W/$n.svg"
  else drawn "$t: render -o" "$W/$n.svg" svg; redraw "$t: render -o, kept" "$W/$n.gp"; fi
  no_canary "$t: render -o"
  rm -f "$W/$n.svg" "$W/$n.gp"

  # fit layout --plot and --plot-script
  run fit layout "$S/default.yaml" "$E/layout_rows.csv" --sigma-mm 0.05 --sigma-deg 0.05 \
      --plot "$W/$n.png" --plot-script "$W/$n.gp"
  if has_ctl "$n"; then refused_name "$t: fit layout --plot" "--plot" "$W/$n.png"
  else drawn "$t: fit layout --plot" "$W/$n.png" png report; redraw "$t: fit layout, kept" "$W/$n.gp"; fi
  no_canary "$t: fit layout --plot"
  rm -f "$W/$n.png" "$W/$n.gp"

  # fit material --plot (an SVG written without gnuplot: its name is in no program)
  run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30 --plot "$W/$n.svg"
  expect_exit 0 "$t: fit material --plot"
  is_svg "$W/$n.svg" && ok || bad "$t: fit material --plot: no SVG under its name"
  no_canary "$t: fit material --plot"
  rm -f "$W/$n.svg"
done

# Picture names that gnuplot opens its own way when written as they are: a relative name
# starting with '|' is a pipe into a shell, '~/' the home folder, '-', '<' and '+' special
# files of `plot`. Each must give the file of exactly that name in W (drawn live and by the
# kept script redrawn by hand), run nothing and write nothing in HOME.
mkdir -p "$W/~" "$W/home"
export HOME="$W/home" # where gnuplot would put a '~/' name
rel=('|touch CANARY;x' '~/tilde' '-dash' '<touch CANARY;y' '+')
for i in "${!rel[@]}"; do
  n="${rel[$i]}"
  t="relative name $i"
  run plot r.csv -o "$n.png" --size 400x300 --script-out "k$i.gp"
  drawn "$t: plot -o" "$W/$n.png" png
  no_canary "$t: plot -o"
  rm -f "$W/$n.png"
  redraw "$t: plot -o, kept" "k$i.gp"
  is_png "$W/$n.png" && ok || bad "$t: plot -o, kept: no PNG under its name"
  run render "$S/default.yaml" -o "$n.svg" --size 400x300
  drawn "$t: render -o" "$W/$n.svg" svg
  no_canary "$t: render -o"
  run fit layout "$S/default.yaml" "$E/layout_rows.csv" --sigma-mm 0.05 --sigma-deg 0.05 \
      --plot "$n-fit.png"
  drawn "$t: fit layout --plot" "$W/$n-fit.png" png report
  no_canary "$t: fit layout --plot"
  [ -z "$(ls -A "$W/home")" ] && ok || bad "$t: a file was written in HOME"
  rm -f "$W/$n.png" "$W/$n.svg" "$W/$n-fit.png" "$W/k$i.gp" "$W/home/"*
done

# An SVG picture stays well-formed XML whatever text it shows: gnuplot escapes '<' and '&'
# in its SVG text but not "]]>", and writes U+FFFE and U+FFFF (no XML characters) as they are.
svg_ok() { python3 -c 'import sys, xml.dom.minidom as m; m.parse(sys.argv[1])' "$2" 2>/dev/null &&
  ok || bad "$1: the SVG is not well-formed XML"; }
n=$'x]]>y\xef\xbf\xbe\xef\xbf\xbf<z>&amp;'
cp "$W/r.csv" "$W/$n.csv"
run plot "$W/$n.csv" -o "$W/xml_title.svg" --size 400x300
drawn "xml text: plot RESULT" "$W/xml_title.svg" svg; svg_ok "xml text: plot RESULT" "$W/xml_title.svg"
python3 - "$n" "$W/r.csv" "$W/xml_col.csv" <<'PY2'
import os, sys
name, src, out = os.fsencode(sys.argv[1]), sys.argv[2], sys.argv[3]
open(out, "wb").write(open(src, "rb").read().replace(b"base_neck_left_pressure_pa",
                                                       name + b"_pressure_pa"))
PY2
run plot "$W/xml_col.csv" -o "$W/xml_col.svg" --size 400x300
drawn "xml text: plot, column name" "$W/xml_col.svg" svg
svg_ok "xml text: plot, column name" "$W/xml_col.svg"
scene_named 'x]]>y<z>&amp;' "$S/default.yaml" "$W/xml.yaml" # YAML refuses U+FFFE, U+FFFF
run render "$W/xml.yaml" -o "$W/xml_scene.svg" --size 400x300
drawn "xml text: render, scene name" "$W/xml_scene.svg" svg
svg_ok "xml text: render, scene name" "$W/xml_scene.svg"

# A NUL byte inside a column name is refused by file:line before anything is drawn; a
# picture name of 15 folders of 120 'é' and '@`' each (about 1850 bytes, 9 KB escaped) draws
# under that name, live and redrawn by hand.
python3 - "$W/r.csv" "$W/nul.csv" <<'PY2'
import sys
open(sys.argv[2], "wb").write(open(sys.argv[1], "rb").read().replace(
    b"base_neck_left_pressure_pa", b"a\x00b_pressure_pa"))
PY2
run plot "$W/nul.csv" -o "$W/nul.png" --size 400x300
expect_exit 65 "NUL in a column name"; expect_stderr_has "nul.csv:" "NUL in a column name"
deep=""
for i in $(seq 15); do deep="$deep$(printf 'é%.0s' $(seq 120))@\`/"; done
mkdir -p "$W/$deep"
run plot r.csv -o "$deep/long.png" --size 400x300 --script-out long.gp
drawn "long name: plot -o" "$W/$deep/long.png" png
rm -f "$W/$deep/long.png"
redraw "long name: plot -o, kept" long.gp
is_png "$W/$deep/long.png" && ok || bad "long name: kept script: no PNG under its name"

# The benchmark lab: a hostile --out folder (gnuplot runs in it) and catalogue scene files
# with hostile names (the load chart labels its scenes by file name).
if [ -x "$BENCH" ]; then
  cat_dir="$W/catalogue"
  mkdir -p "$cat_dir"
  for i in "${picked[@]}"; do cp "$S/load_supine.yaml" "$cat_dir/${names[$i]}.yaml"; done
  for i in "${lab[@]}"; do
    out="$W/${names[$i]}"
    mkdir -p "$out"
    "$BENCH" --quick --only ik,load --scenarios "$cat_dir" --out "$out" >"$TMP/out" 2>"$TMP/err"
    rc=$?
    expect_exit 0 "bench, --out name $i"
    for p in ik_pareto.png load.png; do
      is_png "$out/$p" && ok || bad "bench, --out name $i: no $p"
    done
    for p in ik_pareto.svg load.svg; do
      is_svg "$out/$p" && ok || bad "bench, --out name $i: no $p"
    done
    no_canary "bench, --out name $i" "$out"
    (cd "$out" && gnuplot load.gp >/dev/null 2>&1 && gnuplot ik_pareto.gp >/dev/null 2>&1)
    no_canary "bench, --out name $i, scripts redrawn by hand" "$out"
  done
else
  echo "note: no $BENCH (HP_BUILD_BENCH=OFF, or not built): the lab's charts are not checked"
fi
finish
