#!/usr/bin/env bash
# Installs the built project into a temporary prefix and builds examples/*.c against the
# installed files twice, as C11 with warnings as errors: through find_package(headplan) and
# through pkg-config. Both builds must run and agree. The README's library example
# (examples/plan_scene.c, which must be the README's C block verbatim) must give the same
# pressures, bit for bit, as `headplan solve --json` on the same scene: the library and the
# command line plan a scene at the same fidelity.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR [HEADPLAN_BINARY]
set -euo pipefail
build="$1"; src="$2"; cli="${3:-$1/headplan}"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
cmake --install "$build" --prefix "$prefix" >"$tmp/install.log"
test -f "$prefix/include/headplan/hp_planner.h"
test -f "$prefix/include/headplan/hp_version.h"
libdir=$(dirname "$(find "$prefix" -name 'libheadplan.so' | head -1)")
test -n "$libdir"

# Man pages (when help2man built them): one per subcommand of `headplan --help`, installed
# gzipped (Debian policy; man reads them so), each with a SYNOPSIS that is its own usage line.
if [ -d "$build/man/man1" ]; then
  man1="$prefix/share/man/man1"
  if ls "$man1"/*.1 >/dev/null 2>&1; then echo "man pages installed uncompressed: $(ls "$man1"/*.1 | head -3)"; exit 1; fi
  for cmd in "" $("$cli" --help | sed -n '/^commands:$/,/^$/p' | sed '1d' | awk '{print $1}'); do
    page="$man1/headplan${cmd:+-$cmd}.1.gz"
    [ -f "$page" ] || { echo "no man page $page"; exit 1; }
    gzip -t "$page" || { echo "$page: not gzip"; exit 1; }
    syn=$(gzip -dc "$page" | sed -n '/^\.SH SYNOPSIS$/,/^\.SH/p')
    [ -n "$syn" ] || { echo "$page: no SYNOPSIS section"; exit 1; }
    grep -q "headplan${cmd:+ $cmd}" <<<"$syn" || { echo "$page: SYNOPSIS does not name headplan${cmd:+ $cmd}: $syn"; exit 1; }
  done
fi

# 1. CMake package
cmake -S "$src/examples" -B "$tmp/cmake-build" -DCMAKE_PREFIX_PATH="$prefix" \
      -DCMAKE_BUILD_TYPE=Release >"$tmp/cmake.log"
cmake --build "$tmp/cmake-build" >>"$tmp/cmake.log"
LD_LIBRARY_PATH="$libdir" "$tmp/cmake-build/plan_correction" >"$tmp/out1"
grep -q "status reached" "$tmp/out1"
grep -q "status closest" "$tmp/out1"
scenes=("$src/scenarios/default.yaml" "$src/scenarios/saturation.yaml"
        "$src/scenarios/large_rotation.yaml" "$src/scenarios/sphere_head.yaml")
for sc in "${scenes[@]}"; do
  LD_LIBRARY_PATH="$libdir" "$tmp/cmake-build/plan_scene" "$sc" >"$tmp/ex_$(basename "$sc")" || true
done

# 2. pkg-config: the installed headplan.pc finds its prefix from its own place
#    (${pcfiledir}), so it works wherever `cmake --install --prefix` put it.
export PKG_CONFIG_PATH="$libdir/pkgconfig${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
test "$(pkg-config --variable=includedir headplan | xargs realpath)" = "$(realpath "$prefix/include")"
pc() { pkg-config "$@" headplan; }
cc -std=c11 -Wall -Werror "$src/examples/plan_correction.c" -o "$tmp/pc_example" \
   $(pc --cflags) $(pc --libs) -lm -Wl,-rpath,"$libdir"
"$tmp/pc_example" >"$tmp/out2"
cmp "$tmp/out1" "$tmp/out2" >/dev/null || { echo "the two builds disagree"; exit 1; }
cc -std=c11 -Wall -Wextra -Wshadow -Wpedantic -Werror "$src/examples/plan_scene.c" \
   -o "$tmp/pc_plan_scene" $(pc --cflags) $(pc --libs) -lm -Wl,-rpath,"$libdir"

# A C-only program links the static library too (CMake above; pkg-config --static here)
# and plans exactly as the shared-library build does.
cc -std=c11 -Wall -Wextra -Wshadow -Wpedantic -Werror "$src/examples/plan_scene.c" \
   -o "$tmp/pc_plan_scene_static" $(pc --cflags) "$libdir/libheadplan.a" $(pkg-config --static --libs-only-l --libs-only-L headplan | sed 's/-lheadplan//') -lm
for sc in "${scenes[@]}"; do
  "$tmp/pc_plan_scene_static" "$sc" >"$tmp/static.out" || true
  "$tmp/cmake-build/plan_scene_static" "$sc" >"$tmp/static_cmake.out" || true
  cmp "$tmp/static.out" "$tmp/ex_$(basename "$sc")" >/dev/null &&
    cmp "$tmp/static_cmake.out" "$tmp/ex_$(basename "$sc")" >/dev/null ||
    { echo "$sc: the static builds disagree with the shared one"; exit 1; }
done

# The ABI boundary: the installed shared library exports exactly the functions the
# installed public headers declare (scripts/hp_api.py lists them), nothing more or less.
nm -D --defined-only "$libdir/libheadplan.so" | awk '{ print $3 }' | sort >"$tmp/exported"
python3 "$src/scripts/hp_api.py" list "$prefix"/include/headplan/*.h | sort >"$tmp/declared"
if ! cmp -s "$tmp/exported" "$tmp/declared"; then
  echo "exported symbols differ from the public headers' functions (< declared only, > exported only):"
  diff "$tmp/declared" "$tmp/exported" | grep '^[<>]' | head -20
  exit 1
fi
[ "$(wc -l <"$tmp/declared")" -ge 50 ] || { echo "too few public functions listed"; exit 1; }

# The README's C block is examples/plan_scene.c, verbatim.
awk '/^```c$/ { on = 1; next } /^```$/ { if (on) exit } on' "$src/README.md" >"$tmp/readme.c"
cmp "$tmp/readme.c" "$src/examples/plan_scene.c" >/dev/null \
  || { echo "README's C block differs from examples/plan_scene.c"; diff "$tmp/readme.c" "$src/examples/plan_scene.c" | head; exit 1; }

# The example and `headplan solve --json` agree bit for bit (17 significant digits read
# back as the same double), on every scene tried; both builds of the example print the same.
checked=0
for sc in "${scenes[@]}"; do
  ex="$tmp/ex_$(basename "$sc")"
  "$tmp/pc_plan_scene" "$sc" >"$ex.pc" || true
  cmp "$ex" "$ex.pc" >/dev/null || { echo "$sc: the two example builds disagree"; exit 1; }
  "$cli" solve "$sc" --json >"$ex.json" || true
  python3 - "$ex" "$ex.json" "$sc" <<'PY' || exit 1
import json, sys
ex = open(sys.argv[1]).read().split("\n")
cli = json.load(open(sys.argv[2]))
status = ex[0].split()[1]
if status != cli["status"]:
    sys.exit(f"{sys.argv[3]}: example says {status}, headplan solve says {cli['status']}")
rows = [l.split() for l in ex[1:] if l and not l.startswith("message")]
if len(rows) != len(cli["bladders"]):
    sys.exit(f"{sys.argv[3]}: {len(rows)} bladders in the example, {len(cli['bladders'])} in solve")
for (name, p), b in zip(rows, cli["bladders"]):
    if name != b["name"] or float(p) != b["pressure_pa"]:
        sys.exit(f"{sys.argv[3]}: {name}: example {p} Pa, headplan solve {b['pressure_pa']!r} Pa")
PY
  checked=$((checked + 1))
done
[ "$checked" -eq "${#scenes[@]}" ] || { echo "only $checked scenes compared"; exit 1; }
echo "1 passed, 0 failed"
