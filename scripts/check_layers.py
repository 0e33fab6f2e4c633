#!/usr/bin/env python3
"""The include graph runs one way, and no two files of one folder depend on each other.

The layer order is read from cmake/layers.txt (the one place it is written; CMake builds its
link graph from the same file). A module may include its own files and those of the modules
it reaches through the USES of its line; the public headers belong to the module that
implements them (PUBLIC below). The umbrella headplan.h includes every public header, so
only the programs (KIND prog), which reach every library module, may include it. The
programs may include the shared test helpers under tests/support/ (the backend benchmark
times the backends through the test's planner factory). Tests, fuzzers, examples and the
Python module sit above everything and are not checked.

Inside one folder, the .c/.cpp files form a graph: a file depends on another when it calls a
function, or names a table, that the other defines with external linkage. That graph has no
cycle (a cycle means two files that are one concern split in two, or a helper that belongs
in a third file both use).

Usage: check_layers.py SOURCE_DIR [LAYERS_FILE]
  LAYERS_FILE defaults to SOURCE_DIR/cmake/layers.txt. Exit 1 and one line per upward or
  sideways include and per cycle."""
import os
import re
import sys

PUBLIC = {  # include/headplan/<header> -> the module that implements it
    "hp_common.h": "common", "hp_version.h": "common", "hp_iab.h": "iab",
    "hp_pose.h": "kinematics", "hp_layout.h": "kinematics", "hp_contact.h": "kinematics",
    "hp_load.h": "kinematics", "hp_planner.h": "planner",
    "hp_horizon.h": "horizon", "hp_trace_plan.h": "horizon", "hp_trace_columns.h": "horizon",
    "hp_scene.h": "scene", "hp_trace.h": "scene",
    "hp_calib.h": "calib", "headplan.h": None,  # the umbrella: programs only
}
# Cycles tolerated while being removed (none now). Each is tolerated only while it is exactly
# as listed: a changed or vanished one fails the check, so its entry goes when the cycle does.
PENDING_CYCLES = set()
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
# Comments, string and character literals, and preprocessor lines: removed before names
# are collected, so that a name in a comment or a message makes no dependency.
NOISE = re.compile(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'|^\s*#[^\n]*',
                   re.S | re.M)
# A definition with external linkage at file scope: a function (its parameter list is
# followed by its body) or an initialised object (a backend table), not `static`.
FUNC_DEF = re.compile(r'^(?!static\b)(?!typedef\b)[A-Za-z_][\w \t\*]*?\b([A-Za-z_]\w*)\s*\(([^;{}]*)\)\s*\{',
                      re.M)
OBJ_DEF = re.compile(r'^(?!static\b)(?!typedef\b)(?:const\s+)?[A-Za-z_]\w*\s+(?:const\s+)?\**([A-Za-z_]\w*)'
                     r'\s*(?:\[[^\]]*\])?\s*=', re.M)
NAME = re.compile(r'[A-Za-z_]\w*')
KEYWORDS = {"if", "for", "while", "switch", "return", "sizeof", "do", "else"}


def read_layers(path):
    """[(kind, module, reach)] in file order; reach = the set of modules it may use."""
    rows, reach = [], {}
    for n, line in enumerate(open(path, encoding="utf-8"), 1):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        if len(words) < 2 or words[0] not in ("lib", "prog"):
            sys.exit(f"{path}:{n}: expected KIND MODULE [USES...] with KIND lib or prog")
        kind, mod, uses = words[0], words[1], words[2:]
        for u in uses:
            if u not in reach:
                sys.exit(f"{path}:{n}: {mod} uses {u}, which is not on an earlier line")
        reach[mod] = {mod}.union(*(reach[u] for u in uses)) if uses else {mod}
        rows.append((kind, mod, reach[mod]))
    return rows


def read_private(path):
    """The private layer: internal headers other modules may include (one path a line)."""
    if not os.path.exists(path):
        return set()
    lines = (ln.split("#")[0].strip() for ln in open(path, encoding="utf-8"))
    return {ln for ln in lines if ln}


def module_of_include(inc, own, modules):
    parts = inc.split("/")
    if parts[0] == "headplan" and len(parts) == 2:
        return PUBLIC.get(parts[1], "?")
    if len(parts) == 1:
        return own  # a sibling file of the same folder
    if parts[:2] == ["tests", "support"]:
        return "tests/support"
    return parts[0] if parts[0] in modules else "?"


def file_cycles(folder, names):
    """The cycles among the C files of one folder, each as a list of file names."""
    defs, text = {}, {}
    for f in names:
        if not f.endswith((".c", ".cpp")):
            continue
        src = NOISE.sub(" ", open(os.path.join(folder, f), encoding="utf-8").read())
        text[f] = src
        for m in FUNC_DEF.finditer(src):
            if m.group(1) not in KEYWORDS:
                defs.setdefault(m.group(1), f)
        for m in OBJ_DEF.finditer(src):
            defs.setdefault(m.group(1), f)
    edges = {f: sorted({defs[w] for w in set(NAME.findall(src))
                        if w in defs and defs[w] != f}) for f, src in text.items()}
    # Tarjan's strongly connected components; a component of two or more files is a cycle.
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
    layers = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "cmake", "layers.txt")
    rows = read_layers(layers)
    kinds = {mod: kind for kind, mod, _ in rows}
    reach = {mod: r for _, mod, r in rows}
    libs = {mod for kind, mod, _ in rows if kind == "lib"}
    bad, files = [], []
    pending = {p for p in PENDING_CYCLES if os.path.isdir(os.path.join(root, p[0]))}
    for _, mod, _ in rows:
        d = os.path.join(root, mod)
        if not os.path.isdir(d):
            continue
        names = sorted(os.listdir(d))
        files += [(mod, os.path.join(d, f)) for f in names if f.endswith((".c", ".h", ".cpp"))]
        for comp in file_cycles(d, names):
            if (mod, tuple(comp)) in PENDING_CYCLES:
                pending.discard((mod, tuple(comp)))
                continue
            bad.append(f"{mod}/: the files {', '.join(comp)} depend on each other (a cycle)")
    private = read_private(os.path.join(root, "cmake", "private_headers.txt"))
    inc_dir = os.path.join(root, "include", "headplan")
    for f in sorted(os.listdir(inc_dir)) if os.path.isdir(inc_dir) else []:
        if f.endswith((".h", ".h.in")):
            mod = PUBLIC.get(f.replace(".h.in", ".h"), "?")
            if mod is not None:
                files.append((mod, os.path.join(inc_dir, f)))
    for mod, path in files:
        rel = os.path.relpath(path, root)
        if mod not in reach:
            bad.append(f"{rel}: public header with no module (add it to PUBLIC in {sys.argv[0]})")
            continue
        for inc in INCLUDE.findall(open(path, encoding="utf-8").read()):
            tgt = module_of_include(inc, mod, reach)
            if tgt is None:
                if not libs <= reach[mod]:
                    bad.append(f"{rel}: includes the umbrella {inc} (programs only)")
            elif tgt == "tests/support":
                if kinds[mod] != "prog":
                    bad.append(f"{rel}: includes the test helper {inc} (programs only)")
            elif tgt == "?" or tgt not in reach:
                bad.append(f"{rel}: includes {inc}, which belongs to no module of {layers}")
            elif tgt not in reach[mod]:
                bad.append(f"{rel}: {mod} includes {inc} from {tgt}, which {mod} does not use "
                           f"(its line in {os.path.relpath(layers, root)})")
            elif tgt != mod and not inc.startswith("headplan/") and inc not in private:
                bad.append(f"{rel}: includes {inc}, an internal header of {tgt} not in the "
                           f"private layer (cmake/private_headers.txt)")
    for mod, comp in sorted(pending):
        bad.append(f"{mod}/: {', '.join(comp)} no longer form a cycle: delete its line in "
                   f"PENDING_CYCLES ({sys.argv[0]})")
    for b in bad:
        print(b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
