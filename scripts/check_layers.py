#!/usr/bin/env python3
"""The include graph runs one way: no file includes anything from a layer above its own.

Layers, bottom up (a module may include its own files and those of the layers below):
  common < iab < kinematics < planner < scene < calib < horizon < cli < bench
The public headers belong to the layer of the module that implements them (PUBLIC below).
The umbrella headplan.h includes every public header, so only the layers above the library
(cli, bench) may include it. Tests, fuzzers, examples and the Python module sit above
everything and are not checked.
Usage: check_layers.py SOURCE_DIR   (exit 1 and one line per upward include)"""
import os
import re
import sys

LAYERS = ["common", "iab", "kinematics", "planner", "scene", "calib", "horizon", "cli", "bench"]
PUBLIC = {  # include/headplan/<header> -> the module that implements it
    "hp_common.h": "common", "hp_version.h": "common", "hp_iab.h": "iab",
    "hp_kinematics.h": "kinematics", "hp_load.h": "kinematics", "hp_planner.h": "planner",
    "hp_horizon.h": "horizon", "hp_trace_plan.h": "horizon", "hp_trace_columns.h": "horizon",
    "hp_load_planner.h": "planner", "hp_scene.h": "scene", "hp_trace.h": "scene",
    "hp_calib.h": "calib", "headplan.h": "horizon",  # the umbrella: the top of the library
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def layer_of_include(inc, own_module):
    parts = inc.split("/")
    if parts[0] == "headplan" and len(parts) == 2:
        mod = PUBLIC.get(parts[1], "?")
        return mod
    if len(parts) == 1:
        return own_module  # a sibling file of the same folder
    return parts[0] if parts[0] in LAYERS else "?"


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
    bad = []
    files = []
    for mod in LAYERS:
        d = os.path.join(root, mod)
        if os.path.isdir(d):
            files += [(mod, os.path.join(d, f)) for f in sorted(os.listdir(d))
                      if f.endswith((".c", ".h", ".cpp"))]
    inc_dir = os.path.join(root, "include", "headplan")
    for f in sorted(os.listdir(inc_dir)):
        if f.endswith((".h", ".h.in")):
            mod = PUBLIC.get(f.replace(".h.in", ".h"), "?")
            if mod is None:
                continue
            files.append((mod, os.path.join(inc_dir, f)))
    for mod, path in files:
        rel = os.path.relpath(path, root)
        if mod == "?":
            bad.append(f"{rel}: public header with no layer (add it to PUBLIC in {sys.argv[0]})")
            continue
        for inc in INCLUDE.findall(open(path, encoding="utf-8").read()):
            tgt = layer_of_include(inc, mod)
            if tgt is None:
                bad.append(f"{rel}: includes the umbrella {inc} (users only)")
            elif tgt == "?":
                bad.append(f"{rel}: includes {inc}, which belongs to no known layer")
            elif LAYERS.index(tgt) > LAYERS.index(mod):
                bad.append(f"{rel}: {mod} includes {inc} from the {tgt} layer above it")
    for b in bad:
        print(b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
