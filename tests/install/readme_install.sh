#!/usr/bin/env bash
# Does what the README's Install section says, as a new user would, in a fresh copy of the
# tree with a scratch HOME: every runnable ```sh block of that section in order, each in its
# own `bash -e -o pipefail` from the top of the copy, with the one substitution the README
# asks of its reader (prefix="$HOME/.local" for prefix="$PWD/prefix"); then the README's
# Python example, verbatim, with the venv's python from PREFIX/share/headplan (outside the
# tree). The build is this build folder's (its install script, as the docs test links it):
# the README's own build commands are a second full build, which CI's `scripts/test.sh`
# already makes. Then what the blocks rely on: the installed files are stripped, --help and
# the man pages name installed files that exist, the venv's module loads in a fresh shell
# (env -i) with no LD_LIBRARY_PATH and links nothing of the prefix, and the man pages exist
# for every subcommand.
# `python3` is PYTHON, the interpreter the build's module is for (Debian's), as the docs test
# has it: an interpreter earlier on PATH (pyenv) may lack NumPy.
#   readme_install.sh BUILD_DIR SOURCE_DIR PYTHON
set -euo pipefail
build=$(realpath "$1"); src=$(realpath "$2"); py="$3"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail() { echo "readme_install: $*" >&2; exit 1; }

# A fresh copy: the files git knows (tracked, or new and not ignored), else the tree without
# build folders.
copy="$tmp/src"; mkdir "$copy"
if git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
  (cd "$src" && git ls-files -z --cached --others --exclude-standard |
     tar -cf - --null -T - --ignore-failed-read 2>/dev/null) | tar -xf - -C "$copy"
else
  (cd "$src" && tar -cf - --exclude='./build*' .) | tar -xf - -C "$copy"
fi
mkdir "$copy/build"
ln -s "$build/cmake_install.cmake" "$copy/build/cmake_install.cmake"
mkdir -p "$tmp/python3-bin" "$tmp/home"
ln -s "$py" "$tmp/python3-bin/python3"
export HOME="$tmp/home" LC_ALL=C PATH="$tmp/python3-bin:$PATH"
unset LD_LIBRARY_PATH PYTHONPATH PKG_CONFIG_PATH CMAKE_PREFIX_PATH MANPATH

# The Install section's runnable sh blocks, one file each.
awk -v dir="$tmp/blocks" '
  /^## / { inside = ($0 == "## Install") }
  inside && /^```sh$/ { n++; f = sprintf("%s/%02d.sh", dir, n); on = 1; next }
  on && /^```$/ { on = 0; close(f); next }
  on { print > f }' <(mkdir -p "$tmp/blocks"; cat "$src/README.md")
blocks=("$tmp"/blocks/*.sh)
[ "${#blocks[@]}" -ge 5 ] || fail "only ${#blocks[@]} runnable sh blocks in README's Install section"
prefix="$HOME/.local"
for b in "${blocks[@]}"; do
  grep -q '^prefix="\$PWD/prefix"$' "$b" || fail "a block does not start from prefix=\"\$PWD/prefix\": $(head -1 "$b")"
  sed -i 's|^prefix="\$PWD/prefix"$|prefix="$HOME/.local"|' "$b"
  (cd "$copy" && bash -e -o pipefail "$b") >"$b.log" 2>&1 ||
    { tail -20 "$b.log"; fail "README Install block $(basename "$b") failed"; }
done

# The README's Python example, verbatim, from the installed share folder.
awk '/^## Python$/ { inside = 1 } inside && /^```python$/ { on = 1; next }
     on && /^```$/ { exit } on' "$src/README.md" >"$tmp/snippet.py"
[ -s "$tmp/snippet.py" ] || fail "no python block in README's Python section"
(cd "$prefix/share/headplan" && "$copy/.venv/bin/python" "$tmp/snippet.py") ||
  fail "README's Python example failed from $prefix/share/headplan with the venv"

# Stripped: no symbol table in the program, the shared library or the module.
for f in "$prefix/bin/headplan" "$prefix"/lib/libheadplan.so.*.*.* \
         "$prefix"/lib/python3*/dist-packages/headplan*.so; do
  [ -f "$f" ] || fail "$f: not installed"
  if readelf -S "$f" | grep -Eq '\.symtab|\.debug_'; then fail "$f: not stripped"; fi
done

# --help and the man pages name the installed documentation and scenes, which exist.
"$prefix/bin/headplan" solve --help >"$tmp/help"
grep -qx "documentation: $prefix/share/doc/headplan/docs" "$tmp/help" || fail "solve --help: no installed docs"
grep -qx "example scenes: $prefix/share/headplan/scenarios" "$tmp/help" || fail "solve --help: no installed scenes"
# From a build tree (not installed) the help names the checkout's folders instead.
"$build/headplan" --help >"$tmp/help_build"
grep -qx "documentation: docs" "$tmp/help_build" || fail "build tree's --help: not the checkout's docs"
for f in docs/scenes.md docs/load.md README.md LICENSE; do
  [ -f "$prefix/share/doc/headplan/$f" ] || fail "share/doc/headplan/$f not installed"
done
for f in scenarios/default.yaml scenarios/traces/drift_10hz.csv examples/plan_scene.c; do
  [ -f "$prefix/share/headplan/$f" ] || fail "share/headplan/$f not installed"
done
# A scene naming a trace finds it beside itself, from another folder.
(cd "$tmp" && "$prefix/bin/headplan" batch "$prefix/share/headplan/scenarios/default.yaml" \
   --no-progress -o "$tmp/batch.csv") || fail "batch of the installed default scene (its trace)"
n=0
for cmd in $("$prefix/bin/headplan" --help | sed -n '/^commands:$/,/^$/p' | sed '1d' | awk '{print $1}'); do
  page="$prefix/share/man/man1/headplan-$cmd.1.gz"
  [ -f "$page" ] || fail "no man page $page"
  n=$((n + 1))
done
[ "$n" -ge 10 ] || fail "only $n subcommands in headplan --help"
zgrep -q "documentation: $prefix/share/doc/headplan/docs" "$prefix/share/man/man1/headplan-solve.1.gz" ||
  fail "headplan-solve.1.gz does not name the installed docs"
if zgrep -q "documentation: docs" "$prefix"/share/man/man1/*.1.gz; then fail "a man page names the source tree's docs"; fi

# The venv's module in a fresh shell: no LD_LIBRARY_PATH, nothing of the prefix linked.
mod=$(ls "$copy"/.venv/lib/python3*/site-packages/headplan*.so)
env -i HOME="$HOME" PATH=/usr/bin:/bin bash -c \
  "cd / && '$copy/.venv/bin/python' -c 'import headplan, sys; assert headplan.__file__ == sys.argv[1], headplan.__file__' '$mod'" ||
  fail "the venv's module does not import in a fresh shell"
if ldd "$mod" | grep -q -e "$prefix" -e 'not found'; then fail "$mod links into the prefix"; fi
echo "1 passed, 0 failed"
