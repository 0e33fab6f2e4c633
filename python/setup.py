"""Builds the Python module `headplan` for pip, against an installed headplan library.

    cmake --install build --prefix PREFIX               # the library first (README, Install)
    PKG_CONFIG_PATH=PREFIX/lib/pkgconfig pip install --no-build-isolation ./python

The library is found through pkg-config (headplan.pc). Its static archive, libheadplan.a,
is linked into the module, as the CMake build does: the module then needs no
LD_LIBRARY_PATH, no run path and no other file of the project, only the system's shared
libraries the library itself uses. The module's sources also use three internal headers of
the library (common/, planner/), taken from this source tree: the installed library must be
this tree's version, which is checked. No download: setuptools and NumPy come from the
system (Debian's python3-setuptools and python3-numpy, through a venv made with
--system-site-packages, and --no-build-isolation).
"""
import glob
import os
import re
import shlex
import subprocess
import sys

from setuptools import Extension, setup

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.dirname(HERE)


def fail(msg):
    sys.exit("headplan setup.py: " + msg)


def pkg_config(*args):
    try:
        out = subprocess.run(["pkg-config", *args, "headplan"], check=True,
                             capture_output=True, text=True).stdout
    except FileNotFoundError:
        fail("pkg-config is not installed (Debian: apt-get install pkg-config)")
    except subprocess.CalledProcessError:
        fail("the headplan library is not where pkg-config looks: install it first "
             "(cmake --install build --prefix PREFIX) and set "
             "PKG_CONFIG_PATH=PREFIX/lib/pkgconfig")
    return shlex.split(out)


def source_version():
    with open(os.path.join(SRC, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(headplan VERSION (\S+)", f.read())
    if not m:
        fail(f"no project version in {SRC}/CMakeLists.txt (is python/ inside the source tree?)")
    return m.group(1)


version = source_version()
installed = pkg_config("--modversion")[0]
if installed != version:
    fail(f"the installed headplan is {installed}, this source tree is {version}: "
         "install this tree's build first")
libdir = pkg_config("--variable=libdir")[0]
archive = os.path.join(libdir, "libheadplan.a")
if not os.path.isfile(archive):
    fail(f"{archive}: no such file (the static library is part of the install)")
# The archive's own dependencies (Ipopt, NLopt, libyaml, jansson, libm, libstdc++), without
# the shared library itself.
libs = [a for a in pkg_config("--static", "--libs") if a != "-lheadplan"]
import numpy  # noqa: E402  (after the checks, whose messages are clearer)

ext = Extension(
    "headplan",
    sources=sorted(os.path.basename(p) for p in glob.glob(os.path.join(HERE, "*.c"))),
    include_dirs=[HERE, SRC, numpy.get_include()],
    extra_compile_args=pkg_config("--cflags") + ["-std=c11", "-ffp-contract=off",
                                                 "-fvisibility=hidden"],
    extra_objects=[archive],
    extra_link_args=libs + ["-Wl,--exclude-libs,ALL"],
)
os.chdir(HERE)
setup(
    name="headplan",
    version=version,
    description="Pressures for an eight-bladder soft head-stabilisation robot",
    license="BSD-3-Clause",
    python_requires=">=3.9",
    install_requires=["numpy"],
    ext_modules=[ext],
)
