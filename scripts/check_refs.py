#!/usr/bin/env python3
"""Every document the repository mentions exists in the repository.

Scans the project's text files (docs, sources, tests, scripts, scenes): every `*.md` name
anywhere, and in the Markdown docs every path with a folder (`dir/name.c`), must be in the
tree: as a path from the root, from the mentioning file's folder or from docs/, or (for a
bare name) as the name of some file in the tree. Names that are placeholders by convention (upper case such as
SCENE.yaml or OUT.csv, or a user's own example output such as `x.csv`) are listed in
ALLOWED. Files outside the repository (anything under ../) are always refused.
Usage: check_refs.py SOURCE_DIR   (exit 1 and one line per missing reference)"""
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
SKIP_DIRS = {".git", "build", "build-asan", "build-fuzz", "figures", "__pycache__"}
TEXT_EXT = (".md", ".c", ".h", ".cpp", ".in", ".sh", ".py", ".yaml", ".txt", ".cmake", ".cff")
NAME = re.compile(r"(?<![\w$%{@/.-])((?:\.\./|\./)?(?:[\w-]+/)*[\w-]+\.(?:md|c|h|cpp|yaml|sh|py|cff))\b")
# Placeholders and names a user creates, not files of the project.
ALLOWED = {
    "headplan.h",  # the installed umbrella header, spelled <headplan/headplan.h>
    "IpStdCInterface.h", "nlopt.h", "cmocka.h", "yaml.h", "jansson.h", "Python.h", "sha2.h",
    "nettle/sha2.h",
    "arrayobject.h", "ndarrayobject.h", "numpy/arrayobject.h",
    "stdio.h", "stdlib.h", "string.h", "math.h", "time.h", "errno.h", "unistd.h",
    "quadmath.h", "pthread.h", "signal.h", "fcntl.h", "stdint.h", "float.h", "limits.h",
}


def is_placeholder(name):
    base = os.path.basename(name)
    stem = base.rsplit(".", 1)[0]
    if re.search(r"(^|[_-])[A-Z]{3,}($|[_-])", stem):  # backend_NAME.c, FAMILY_pareto.gp
        return True
    return stem.isupper() or stem.upper() == stem or base in ALLOWED or name in ALLOWED


def main():
    files, names = [], set()
    for d, dirs, fs in os.walk(ROOT):
        dirs[:] = [x for x in dirs if x not in SKIP_DIRS and not x.startswith("build")]
        for f in fs:
            p = os.path.join(d, f)
            files.append(p)
            names.add(f)
    bad = []
    for p in files:
        if not p.endswith(TEXT_EXT) and os.path.basename(p) not in ("CMakeLists.txt",):
            continue
        try:
            text = open(p, encoding="utf-8").read()
        except (UnicodeDecodeError, OSError):
            continue
        rel = os.path.relpath(p, ROOT)
        for ln, line in enumerate(text.split("\n"), 1):
            for m in NAME.finditer(line):
                ref = m.group(1)
                if not ref.endswith(".md") and not (p.endswith(".md") and "/" in ref):
                    continue
                if ref.startswith("../") and not os.path.exists(os.path.join(os.path.dirname(p), ref)):
                    bad.append(f"{rel}:{ln}: {ref}: outside the repository or missing")
                    continue
                if not ref.endswith(".md") and is_placeholder(ref):
                    continue
                cands = [os.path.join(ROOT, ref), os.path.join(os.path.dirname(p), ref),
                         os.path.join(ROOT, "docs", ref), os.path.join(ROOT, "include", ref)]
                # a generated file counts when its template (NAME.in) is in the tree
                if any(os.path.exists(c) or os.path.exists(c + ".in") for c in cands):
                    continue
                if "/" not in ref and ref in names:
                    continue
                if "/" in ref and os.path.basename(ref) in names and ref.count("/") == 1 \
                        and ref.split("/")[0] in ("headplan",):
                    continue
                bad.append(f"{rel}:{ln}: {ref}: no such file in the repository")
    for b in sorted(set(bad)):
        print(b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
