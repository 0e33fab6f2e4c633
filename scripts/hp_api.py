#!/usr/bin/env python3
"""The public API's export list, from the public headers.

  hp_api.py annotate HEADER...   prefix every top-level function declaration with HP_API
                                 (idempotent; run it after adding a public function)
  hp_api.py list HEADER...       print the declared function names, one per line

A declaration is a statement at file scope (outside comments, braces and preprocessor
lines) that is not a typedef and contains a parameter list. The exported-symbols test
compares `list` with the dynamic symbols of the installed shared library."""
import re
import sys


def statements(text):
    """Yields (start_offset, statement_text) of file-scope statements ending in ';'."""
    i, n, depth, start = 0, len(text), 0, None
    while i < n:
        c = text[i]
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = n if j < 0 else j + 2
            continue
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j + 1
            continue
        if c == "#" and (i == 0 or text[i - 1] == "\n"):
            while True:  # a preprocessor line, with continuations
                j = text.find("\n", i)
                if j < 0:
                    i = n
                    break
                if text[j - 1] != "\\":
                    i = j + 1
                    break
                i = j + 1
            continue
        if c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            i = j + 1
            continue
        if c == "{":
            if depth == 0 and start is not None and 'extern "C"' in text[start:i]:
                start = None  # extern "C" { ... } does not nest the declarations
                i += 1
                continue
            depth += 1
        elif c == "}":
            depth = max(depth - 1, 0)
        elif c == ";" and depth == 0:
            if start is not None:
                yield start, text[start:i + 1]
            start = None
            i += 1
            continue
        if depth == 0 and start is None and not c.isspace() and c not in "{};":
            start = i
        i += 1


DECL = re.compile(r"^(?:HP_API\s+)?(?:const\s+)?[A-Za-z_][\w\s\*]*?\b(hp_\w+)\s*\(", re.S)


def functions(text):
    for start, st in statements(text):
        if st.lstrip().startswith(("typedef", "struct", "enum", "}")):
            continue
        m = DECL.match(st)
        if m:
            yield start, m.group(1), st.startswith("HP_API")


def main():
    cmd, files = sys.argv[1], sys.argv[2:]
    for f in files:
        text = open(f).read()
        found = list(functions(text))
        if cmd == "list":
            for _, name, _ in found:
                print(name)
        elif cmd == "annotate":
            for start, _, has in sorted(found, reverse=True):
                if not has:
                    text = text[:start] + "HP_API " + text[start:]
            open(f, "w").write(text)
        else:
            sys.exit("usage: hp_api.py annotate|list HEADER...")


if __name__ == "__main__":
    main()
