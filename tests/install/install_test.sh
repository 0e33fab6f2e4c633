#!/usr/bin/env bash
# Installs the built project into a temporary prefix and builds examples/plan_correction.c
# against the installed files twice: through find_package(headplan) and through pkg-config.
# Both programs must run and exit 0. Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1"; src="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
cmake --install "$build" --prefix "$prefix" >"$tmp/install.log"
test -f "$prefix/include/headplan/hp_planner.h"
test -f "$prefix/include/headplan/hp_version.h"
libdir=$(dirname "$(find "$prefix" -name 'libheadplan.so' | head -1)")
test -n "$libdir"

# 1. CMake package
cmake -S "$src/examples" -B "$tmp/cmake-build" -DCMAKE_PREFIX_PATH="$prefix" \
      -DCMAKE_BUILD_TYPE=Release >"$tmp/cmake.log"
cmake --build "$tmp/cmake-build" >>"$tmp/cmake.log"
LD_LIBRARY_PATH="$libdir" "$tmp/cmake-build/plan_correction" >"$tmp/out1"
grep -q "status reached" "$tmp/out1"
grep -q "status closest" "$tmp/out1"

# 2. pkg-config: the installed headplan.pc finds its prefix from its own place
#    (${pcfiledir}), so it works wherever `cmake --install --prefix` put it.
export PKG_CONFIG_PATH="$libdir/pkgconfig${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
test "$(pkg-config --variable=includedir headplan | xargs realpath)" = "$(realpath "$prefix/include")"
pc() { pkg-config "$@" headplan; }
cc -std=c11 -Wall -Werror "$src/examples/plan_correction.c" -o "$tmp/pc_example" \
   $(pc --cflags) $(pc --libs) -lm -Wl,-rpath,"$libdir"
"$tmp/pc_example" >"$tmp/out2"
cmp "$tmp/out1" "$tmp/out2" >/dev/null || { echo "the two builds disagree"; exit 1; }
echo "1 passed, 0 failed"
