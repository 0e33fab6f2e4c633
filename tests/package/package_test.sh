#!/usr/bin/env bash
# The Debian packages in a clean Debian 12: builds the four .debs from this build (cpack,
# cmake/package.cmake), installs them with apt (which brings in the dependencies they state,
# and only those) into a fresh minimal root, and there runs a scene from /usr, compiles and
# runs a C program through pkg-config, and imports the Python module.
#
# The clean root is `debootstrap --variant=minbase bookworm` (plus a compiler, pkg-config and
# python3, what a user compiling a program has), from the Debian archive this machine's apt
# uses; made once and cached as a tarball under CACHE_DIR (with apt's downloaded packages),
# unpacked afresh for every run. Needs root (chroot) and that archive; otherwise skipped
# (exit 77) saying why.
#   package_test.sh BUILD_DIR CACHE_DIR
set -euo pipefail
build=$(realpath "$1"); cache="$2"
skip() { echo "package_test: skipped: $*"; exit 77; }
fail() { echo "package_test: $*" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || skip "needs root for debootstrap and chroot"
command -v debootstrap >/dev/null || skip "debootstrap not installed (scripts/install-deps.sh)"
command -v cpack >/dev/null || skip "cpack not found"
mkdir -p "$cache/apt-archives/partial"
cache=$(realpath "$cache")
tmp=$(mktemp -d)
root="$tmp/root"
cleanup() {
  for m in proc dev/pts dev var/cache/apt/archives; do
    mountpoint -q "$root/$m" 2>/dev/null && umount -l "$root/$m"
  done
  rm -rf --one-file-system "$tmp"
}
trap cleanup EXIT
t0=$SECONDS

# The archive apt uses here (deb822 or one-line sources), else Debian's own.
mirror=$(sed -n 's/^URIs: *\(\S*\/debian\)\/*$/\1/p' /etc/apt/sources.list.d/*.sources 2>/dev/null | head -1)
[ -n "$mirror" ] || mirror=$(awk '$1 == "deb" && $2 ~ /\/debian\/?$/ { print $2; exit }' \
                             /etc/apt/sources.list 2>/dev/null || true)
mirror=${mirror:-http://deb.debian.org/debian}

# 1. The packages.
cpack -G DEB --config "$build/CPackConfig.cmake" -B "$tmp/debs" >"$tmp/cpack.log" 2>&1 ||
  { tail -20 "$tmp/cpack.log"; fail "cpack failed"; }
for p in libheadplan0 libheadplan-dev headplan python3-headplan; do
  ls "$tmp/debs/${p}_"*.deb >/dev/null 2>&1 || fail "no package $p"
done
dpkg-deb -f "$tmp/debs"/libheadplan-dev_*.deb Depends | grep -q 'libheadplan0 (= ' ||
  fail "libheadplan-dev does not depend on its libheadplan0"
echo "packages built in $((SECONDS - t0)) s"

# 2. The clean root, from the cached tarball (made on first use).
base="$cache/bookworm-minbase.tar.gz"
include=gcc,libc6-dev,pkg-config,python3
if [ ! -f "$base" ] || [ "$(cat "$base.include" 2>/dev/null)" != "$include" ]; then
  mkdir "$tmp/base"
  debootstrap --variant=minbase --include="$include" bookworm "$tmp/base" "$mirror" \
    >"$tmp/debootstrap.log" 2>&1 || { tail -5 "$tmp/debootstrap.log"; skip "debootstrap from $mirror failed"; }
  tar -C "$tmp/base" --one-file-system -czf "$base.part" .
  mv "$base.part" "$base"; echo "$include" >"$base.include"
  rm -rf --one-file-system "$tmp/base"
  echo "clean root made and cached in $((SECONDS - t0)) s"
fi
mkdir "$root"
tar -C "$root" -xzf "$base"
cp /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
# This machine's suites (with updates and security), so the root matches what the packages
# were built against.
if ls /etc/apt/sources.list.d/*.sources >/dev/null 2>&1; then
  rm -f "$root/etc/apt/sources.list"
  cp /etc/apt/sources.list.d/*.sources "$root/etc/apt/sources.list.d/"
fi
mount -t proc proc "$root/proc" || skip "cannot mount /proc in the clean root (no mount permission)"
mount --bind "$cache/apt-archives" "$root/var/cache/apt/archives" ||
  skip "cannot bind-mount the download cache into the clean root"
mkdir "$root/debs"; cp "$tmp/debs"/*.deb "$root/debs/"
in_root() { chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin LC_ALL=C \
            DEBIAN_FRONTEND=noninteractive HOME=/root "$@"; }

# 3. Install: apt resolves the dependencies the packages state from the archive.
in_root apt-get update -qq >"$tmp/apt.log" 2>&1 || { tail -5 "$tmp/apt.log"; skip "apt-get update from $mirror failed"; }
debs=(); for d in "$root"/debs/*.deb; do debs+=("/debs/$(basename "$d")"); done
in_root apt-get install -y -qq --no-install-recommends "${debs[@]}" >>"$tmp/apt.log" 2>&1 ||
  { tail -20 "$tmp/apt.log"; fail "apt-get install of the packages failed"; }
echo "installed in the clean root after $((SECONDS - t0)) s"

# 4. Use them there, from another folder than the data.
in_root bash -euo pipefail -c '
cd /root
headplan solve /usr/share/headplan/scenarios/default.yaml --json >solve.json
grep -q "\"status\": \"reached\"" solve.json
headplan --help | grep -qx "documentation: /usr/share/doc/headplan/docs"
test -f /usr/share/doc/headplan/docs/scenes.md
test -f /usr/share/man/man1/headplan-solve.1.gz
zgrep -q "documentation: /usr/share/doc/headplan/docs" /usr/share/man/man1/headplan-solve.1.gz
cc -std=c11 -Wall -Wextra -Werror /usr/share/headplan/examples/plan_scene.c -o plan_scene \
   $(pkg-config --cflags --libs headplan) -lm
./plan_scene /usr/share/headplan/scenarios/default.yaml | grep -qx "status reached"
python3 -c "import headplan, sys
r = headplan.Planner(headplan.load_scene(\"/usr/share/headplan/scenarios/default.yaml\")).plan([1, 0, -0.5, 0.3, 0, -0.2])
assert r[\"status\"] == \"reached\", r[\"status\"]
print(\"python3-headplan\", headplan.__version__, \"from\", headplan.__file__)"
' || fail "the installed packages do not work in the clean root"
echo "package test took $((SECONDS - t0)) s"
echo "1 passed, 0 failed"
