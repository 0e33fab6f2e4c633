# The docs runner itself (run_doc_blocks.py): on a small markdown file it runs the ```sh
# blocks and the `$ ` lines of ```console blocks, names the block that fails by FILE:LINE,
# stops one that runs too long, lists a no-run block with its reason, and refuses blocks that
# do not say what they are; python blocks share one session with the build's module folder
# on their path. Run as: bash selftest.sh RUNNER BUILD_DIR SOURCE_DIR.
RUNNER=$1 BUILD=$2 SRC=$3
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fails=0
check() { grep -qF -- "$1" "$T/log" || { echo "FAIL: output lacks '$1'"; fails=$((fails+1)); }; }
cat > "$T/good.txt" <<'MD'
# good
```sh
headplan --version > v.txt
test "$HP_DOC_SMALL" = 1
```
```console
$ grep -q headplan v.txt && \
    test -f build/headplan
output not compared
```
```sh no-run: needs a cluster
sbatch job.sh
```
```python
import os
x = os.environ["PYTHONPATH"]
```
```python
assert x.endswith("/build/python"), x
```
MD
python3 "$RUNNER" --src "$SRC" --bin "$BUILD" "$T/good.txt" > "$T/log" 2>&1
rc=$?
[ "$rc" -eq 0 ] || { echo "FAIL: good.txt: exit $rc"; cat "$T/log"; fails=$((fails+1)); }
check "4 blocks run, 0 failed; 1 not run"
check "skip $T/good.txt:11: needs a cluster"

cat > "$T/bad.txt" <<'MD'
# bad
```sh
true
```

```sh
headplan solve scenarios/no_such_scene.yaml
```
```sh
sleep 3600
```
```
untyped
```
```sh no-run
x
```

    headplan solve scenarios/default.yaml

```python
y = 1
```
```python
assert y == 2, "y is not 2"
```
MD
# A block that never ends within the timeout (an hour's sleep) is stopped whatever the
# machine's speed; the timeout leaves the other blocks (a few milliseconds of CPU each)
# time enough on a machine loaded hundreds of times over (they missed a 2 s timeout on a
# 0.5 % CPU share).
python3 "$RUNNER" --src "$SRC" --bin "$BUILD" --timeout 30 "$T/bad.txt" > "$T/log" 2>&1
rc=$?
[ "$rc" -eq 1 ] || { echo "FAIL: bad.txt: exit $rc, want 1"; fails=$((fails+1)); }
check "FAIL $T/bad.txt:6: exit 66"
check "no_such_scene.yaml"
check "FAIL $T/bad.txt:9: timed out after 30 s"
check "FAIL $T/bad.txt:12: a fenced block without a kind"
check "FAIL $T/bad.txt:15: \`\`\`sh takes only 'no-run: REASON'"
check "FAIL $T/bad.txt:19: a command in an indented block"
check "FAIL $T/bad.txt:24: exit 1"
check "y is not 2"
check "5 blocks run, 3 failed"
[ "$fails" -eq 0 ] || { cat "$T/log"; exit 1; }
echo "selftest passed"
