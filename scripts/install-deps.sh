#!/usr/bin/env bash
# Installs every Debian 12 package headplan needs to build, test, fuzz, benchmark and plot.
# Safe to run again: it installs only what is missing. Needs root (or sudo) on first use.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git
  coinor-libipopt-dev   # Ipopt 3.11 C interface (reference NLP backend)
  libnlopt-dev          # NLopt 2.7 (SLSQP, COBYLA)
  libeigen3-dev         # Eigen 3.4 (SVD, QR, least squares)
  libyaml-dev           # libyaml: scene files with line:column marks
  libjansson-dev        # jansson: JSON output and JSON Lines traces
  nettle-dev            # Nettle: SHA-256 of batch inputs (with the CPU's SHA instructions)
  libcmocka-dev         # cmocka: unit-test framework
  gnuplot-nox           # charts (PNG, SVG)
  clang libclang-rt-14-dev  # libFuzzer targets and sanitizer runtimes
  valgrind cppcheck
  python3 python3-numpy python3-scipy  # peer benchmark (SciPy SLSQP)
  python3-dev python3-pytest python3-matplotlib  # Python module, its tests, its pictures
  parallel              # the GNU parallel sharding recipe is run by the tests
  slurm-wlm munge       # the Slurm recipe runs on a single-node Slurm its test starts
  python3-distributed   # Dask: the Python study recipe runs on a LocalCluster in its test
  locales               # de_DE locale source: the comma-locale tests build it with localedef
  help2man man-db       # man pages generated from --help at build time; `man headplan`
  python3-venv python3-pip python3-setuptools python3-wheel  # pip install ./python, offline
  debootstrap           # the package test's clean Debian 12 root (tests/package/)
  calculix-ccx          # CalculiX: the finite-element reference of fem/ (ctest -L fem)
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present" >&2
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
