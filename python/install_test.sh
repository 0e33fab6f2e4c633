#!/usr/bin/env bash
# Installs the project into a temporary prefix and imports the installed Python module from
# there (PYTHONPATH at the prefix's site folder), outside the build tree, with no
# LD_LIBRARY_PATH: the module carries the library inside it.
#   install_test.sh BUILD_DIR SOURCE_DIR PYTHON SITE_DIR
set -euo pipefail
build="$1"; src="$2"; py="$3"; site="$4"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >"$tmp/install.log"
mod=$(find "$tmp/prefix/$site" -name 'headplan*.so' | head -1)
test -n "$mod" || { echo "no module under $tmp/prefix/$site"; exit 1; }
cd "$tmp"
unset LD_LIBRARY_PATH
PYTHONPATH="$tmp/prefix/$site" "$py" - "$src/scenarios/default.yaml" "$tmp/prefix/$site" <<'PY'
import sys, headplan
assert headplan.__file__.startswith(sys.argv[2]), headplan.__file__
r = headplan.Planner(headplan.load_scene(sys.argv[1])).plan([1, 0, -0.5, 0.3, 0, -0.2])
assert r["status"] == "reached", r["status"]
print("installed module:", headplan.__file__)
PY
# The module needs no other file of the prefix: only system libraries and Python.
if ldd "$mod" | grep -q "$tmp/prefix"; then echo "the module links into the prefix"; exit 1; fi
echo "1 passed, 0 failed"
