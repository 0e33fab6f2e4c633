# headplan plot hashes its trace (--trace, or the --scene's own) before it reads it: a
# trace that never ends (/dev/zero, a FIFO nobody writes, a device) is refused by name
# (66) at once instead of being read forever. Every run is bounded by `timeout`, so a
# command that would hang fails this test (exit 124) instead of hanging it; the bound is a
# hang's, not a time the test expects (the last run draws a picture: about 0.4 s idle, and
# under the sanitizers on a loaded machine many times that).
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"
trun() { timeout -k 5 120 "$HP_BIN" "$@" >"$TMP/out" 2>"$TMP/err"; rc=$?; }

mkdir -p "$TMP/sc/traces"
cp "$S/nodding.yaml" "$TMP/sc/nodding.yaml"
cp "$S/traces/nodding.csv" "$TMP/sc/traces/nodding.csv"
"$HP_BIN" batch "$TMP/sc/nodding.yaml" -o "$TMP/r.csv" --no-progress --no-times 2>/dev/null ||
  bad "batch of the result to draw"
mkfifo "$TMP/fifo.csv"

# --trace: a character device, a FIFO, a folder
for t in /dev/zero "$TMP/fifo.csv" "$TMP/sc"; do
  trun plot "$TMP/r.csv" --trace "$t" -o "$TMP/x.png"
  expect_exit 66 "plot --trace $t"
  expect_stderr_has "--trace $t: not a regular file" "plot --trace $t"
  [ ! -e "$TMP/x.png" ] && ok || bad "plot --trace $t: a picture was written"
done

# The scene's own trace turned into a FIFO after the result was planned (the scene's text,
# and so its hash, unchanged).
rm "$TMP/sc/traces/nodding.csv"
mkfifo "$TMP/sc/traces/nodding.csv"
trun plot "$TMP/r.csv" --scene "$TMP/sc/nodding.yaml" -o "$TMP/x.png"
expect_exit 66 "plot --scene whose trace is a FIFO"
expect_stderr_has "the scene's trace $TMP/sc/traces/nodding.csv: not a regular file" \
  "plot --scene whose trace is a FIFO"

# A regular trace still draws.
trun plot "$TMP/r.csv" --trace "$S/traces/nodding.csv" -o "$TMP/x.png" --size 400x300
expect_exit 0 "plot --trace regular"
finish
