#!/usr/bin/env python3
"""Runs the commands the documentation shows, so a stale command fails the test suite.

    run_doc_blocks.py --src SOURCE_DIR --bin BUILD_DIR [--python PY] [--timeout S] [MARKDOWN...]

Without files: the README and every Markdown file of docs/ in SOURCE_DIR. How a block is marked (the
fence's info string, whose first word is the language a renderer shows):

  ```sh                      commands, run as written
  ```console                 a transcript: every `$ ` line (with its `\\` continuations) is
                             run as a command; the output shown is not compared
  ```python                  run in one Python session per file, the file's python blocks
                             in order (a later block uses the names an earlier one made)
  ```sh no-run: REASON       shown, never run (root, a package or machine not here, a second
  ```console no-run: REASON  build tree, minutes of work); REASON is required and listed
  ```text, ```yaml, ```c, ```python, ...   not commands: never run

A fenced block without a kind, and an indented code block that starts with a command
(`headplan`, `build/...`, `bash`, `$ `, ...), are errors: a command must say which it is.

The blocks of one file run in order, each with `bash -e -o pipefail`, in one scratch copy of
the source tree per file (so a walk-through's later blocks see the files its earlier ones
wrote, and nothing is written into the sources). BUILD_DIR's programs are on PATH and in the
copy's `build/` (`headplan`, `headplan-bench*`, `build/python`; `cmake --install build`
installs that build), and --python, the python3
the module was built for, is `python3`. HP_DOC_SMALL=1 is set: a
command that takes long at full size asks for a small one with it, as in
`headplan-bench --out docs/figures ${HP_DOC_SMALL:+--quick}`. A block that fails, or runs
longer than --timeout seconds, is reported as FILE:LINE with its status and the end of its
output; the exit status is 1 if any block failed or any marking is wrong, else 0.
"""
import argparse
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

COMMAND_WORD = re.compile(
    r"^(\$|headplan\S*|\./\S+|build[^/\s]*/\S+|bench/\S+|scripts/\S+|bash|sh|cmake|ctest|"
    r"python3?|parallel|sbatch|git|gnuplot|cc|make|[A-Z][A-Z0-9_]*=\S*)$")


class Block:
    def __init__(self, path, line, kind, reason, text):
        self.path, self.line, self.kind, self.reason, self.text = path, line, kind, reason, text

    def where(self):
        return f"{self.path}:{self.line}"


def console_commands(lines):
    """The commands of a transcript: each `$ ` line and its backslash continuations."""
    cmds, cur = [], None
    for ln in lines:
        if cur is not None:
            cur.append(ln)
            if not ln.rstrip().endswith("\\"):
                cmds.append("\n".join(cur))
                cur = None
        elif ln.startswith("$ "):
            cur = [ln[2:]]
            if not ln.rstrip().endswith("\\"):
                cmds.append(ln[2:])
                cur = None
    if cur is not None:
        cmds.append("\n".join(cur))
    return "\n".join(cmds) + "\n" if cmds else ""


def parse(path, shown):
    """The runnable blocks of one markdown file, and the marking errors in it."""
    blocks, errors = [], []
    lines = open(path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        ln = lines[i]
        m = re.match(r"^(```+)(.*)$", ln)
        if m:
            fence, info = m.group(1), m.group(2).strip()
            j = i + 1
            while j < len(lines) and not lines[j].startswith(fence):
                j += 1
            body = lines[i + 1:j]
            start = i + 1
            i = j + 1
            words = info.split(None, 1)
            kind = words[0] if words else ""
            rest = words[1] if len(words) > 1 else ""
            if not kind:
                errors.append(f"{shown}:{start}: a fenced block without a kind "
                              "(```sh to run, ```text or ```console for output)")
                continue
            if kind not in ("sh", "console", "python"):
                continue
            reason = None
            if rest:
                r = re.match(r"^no-run:\s*(\S.*)$", rest)
                if not r:
                    errors.append(f"{shown}:{start}: ```{kind} takes only "
                                  f"'no-run: REASON' after it, not '{rest}'")
                    continue
                reason = r.group(1)
            text = console_commands(body) if kind == "console" else "\n".join(body) + "\n"
            if not text.strip():
                errors.append(f"{shown}:{start}: ```{kind} block with no command in it")
                continue
            blocks.append(Block(shown, start, kind, reason, text))
            continue
        # An indented code block: a run of lines indented by 4 after a blank line.
        if ln.startswith("    ") and ln.strip() and (i == 0 or not lines[i - 1].strip()):
            word = ln.split()[0]
            if COMMAND_WORD.match(word) and not in_list_item(lines, i):
                errors.append(f"{shown}:{i + 1}: a command in an indented block: fence it "
                              "as ```sh (or ```sh no-run: REASON, ```console, ```text)")
            while i < len(lines) and (lines[i].startswith("    ") or not lines[i].strip()):
                i += 1
            continue
        i += 1
    return blocks, errors


def in_list_item(lines, i):
    """True when line i continues a list item (its indent is the item's text, not code)."""
    k = i - 1
    while k >= 0 and not lines[k].strip():
        k -= 1
    return k >= 0 and re.match(r"^\s*([-*+]|\d+\.)\s", lines[k]) is not None


def scratch_copy(src, bindir, dest):
    """The source tree without build trees or git data, with the build's programs in build/."""
    def ignore(d, names):
        if os.path.abspath(d) == src:
            return [n for n in names if n.startswith("build") or n == ".git"]
        return [n for n in names if n == "__pycache__"]
    shutil.copytree(src, dest, ignore=ignore, symlinks=True)
    b = os.path.join(dest, "build")
    os.mkdir(b)
    for name in sorted(os.listdir(bindir)):
        p = os.path.join(bindir, name)
        if (name.startswith("headplan") and os.path.isfile(p) and os.access(p, os.X_OK)) or \
                (name == "python" and os.path.isdir(p)):
            os.symlink(p, os.path.join(b, name))
    # The build's install script (its paths are absolute), so `cmake --install build
    # --prefix DIR` installs this build, as the README's Install section shows, with no
    # second build.
    script = os.path.join(bindir, "cmake_install.cmake")
    if os.path.isfile(script):
        os.symlink(script, os.path.join(b, "cmake_install.cmake"))
    return b


# One Python session for a file's python blocks: each is compiled under its FILE:LINE (so a
# traceback names it) and run in one namespace; the first that raises is named and stops it.
PY_SESSION = """
import sys, traceback
ns = {"__name__": "__main__"}
for where, code in BLOCKS:
    try:
        exec(compile(code, where, "exec"), ns)
    except BaseException:
        traceback.print_exc()
        print("failed in " + where)
        sys.exit(1)
    print("ran " + where)
"""


def run_block(block, cwd, env, timeout, argv=None):
    """(status or None on timeout, seconds, tail of the output)."""
    t0 = time.monotonic()
    argv = argv or ["bash", "-e", "-o", "pipefail", "-c", block.text]
    p = subprocess.Popen(argv, cwd=cwd, env=env,
                         stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, start_new_session=True)
    try:
        out, _ = p.communicate(timeout=timeout)
        rc = p.returncode
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)  # the block's own process group, nothing else
        out, _ = p.communicate()
        rc = None
    tail = out.decode("utf-8", "replace").rstrip("\n").split("\n")[-8:]
    return rc, time.monotonic() - t0, tail


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--src", required=True)
    ap.add_argument("--bin", required=True)
    ap.add_argument("--timeout", type=float, default=120)
    ap.add_argument("--python", help="the python3 the build's module is for (first on PATH)")
    ap.add_argument("--list", action="store_true", help="list the blocks, run nothing")
    ap.add_argument("files", nargs="*")
    a = ap.parse_args()
    src, bindir = os.path.realpath(a.src), os.path.realpath(a.bin)
    if not os.path.isfile(os.path.join(bindir, "headplan")):
        print(f"run_doc_blocks: {bindir}/headplan: no such program (--bin is the build folder)",
              file=sys.stderr)
        return 2
    files = a.files or [os.path.join(src, "README.md")] + sorted(
        glob.glob(os.path.join(src, "docs", "*.md")))
    failed, ran, skipped, errors = [], 0, [], []
    for f in files:
        shown = os.path.relpath(os.path.realpath(f), src)
        if shown.startswith(".."):
            shown = f
        blocks, errs = parse(f, shown)
        errors += errs
        runnable = [b for b in blocks if b.reason is None]
        skipped += [b for b in blocks if b.reason is not None]
        if a.list:
            for b in blocks:
                print(f"{b.where()}: {b.kind}" + (f" no-run: {b.reason}" if b.reason else ""))
            continue
        if not runnable:
            continue
        with tempfile.TemporaryDirectory(prefix="hp_docs_") as tmp:
            root = os.path.join(tmp, "src")
            b_dir = scratch_copy(src, bindir, root)
            path = [b_dir]
            if a.python:  # `python3` in a block is the one the module was built for
                py_dir = os.path.join(tmp, "python3-bin")
                os.mkdir(py_dir)
                os.symlink(a.python, os.path.join(py_dir, "python3"))
                path.append(py_dir)
            env = dict(os.environ, HP_DOC_SMALL="1", LC_ALL="C", TMPDIR=tmp,
                       PATH=os.pathsep.join(path + [os.environ["PATH"]]))
            pys = [b for b in runnable if b.kind == "python"]
            if pys:  # after the shell blocks, in one session with the module on its path
                py = a.python or "python3"
                code = "BLOCKS = %r\n%s" % ([(b.where(), b.text) for b in pys], PY_SESSION)
                env_py = dict(env, PYTHONPATH=os.path.join(b_dir, "python"))
            for b in [b for b in runnable if b.kind != "python"] + pys[:1]:
                if b.kind == "python":
                    rc, secs, tail = run_block(b, root, env_py, a.timeout * len(pys),
                                               [py, "-c", code])
                    ran += len(pys)
                    m = [t for t in tail if t.startswith("failed in ")]
                    label = " ".join(x.where() for x in pys)
                    b = next((x for x in pys if m and x.where() == m[0][10:]), b)
                else:
                    rc, secs, tail = run_block(b, root, env, a.timeout)
                    ran += 1
                    label = b.where()
                if rc == 0:
                    print(f"ok   {label} ({secs:.1f} s)")
                    continue
                why = f"timed out after {a.timeout:g} s" if rc is None else f"exit {rc}"
                failed.append(b.where())
                print(f"FAIL {b.where()}: {why}")
                for t in tail:
                    print(f"     | {t}")
    for b in skipped:
        print(f"skip {b.where()}: {b.reason}")
    for e in errors:
        print(f"FAIL {e}")
    print(f"{ran} blocks run, {len(failed)} failed; {len(skipped)} not run (listed above); "
          f"{len(errors)} marking errors")
    return 1 if failed or errors else 0


if __name__ == "__main__":
    sys.exit(main())
