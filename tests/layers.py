#!/usr/bin/env python3
"""layers.py: check lib/'s include graph against ARCHITECTURE.md's layer table.

usage: layers.py REPO_ROOT

Reads the "| layer | folder | may include |" table of ARCHITECTURE.md, then
every `#include "..."` of every .c/.h file under lib/ and include/ (the
folders the table lists; include/ holds the public flitter.h): the header must live in
the including file's own folder or in a folder its layer may include. Headers
generated at build time (parser.h, from grammar/parser.y) belong to syntax.
Also fails when a header name is not unique across lib/ (includes are
written without a folder), when a file lies outside every listed folder,
when an include names no header of lib/, or when a file of src/ (the
flitter command) includes any library header but the public flitter.h. And
fails when a source file of lib/ or src/ is named nowhere in ARCHITECTURE.md
(a .c or .cpp file, or a header without one of the same name beside it):
the map must place every file. Prints each violation and exits 1; prints a
summary and exits 0 when the graph is clean.
"""
import os
import re
import sys

GENERATED = {"parser.h": "syntax", "gl_names.h": "gl"}


def table_rows(path, header):
    """The body rows (lists of stripped cells) of the Markdown table in
    [path] whose first cells are [header]; [] when there is none."""
    rows, in_table = [], False
    with open(path, encoding="utf-8") as f:
        for line in f:
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if cells[:len(header)] == header:
                in_table = True
                continue
            if in_table:
                if not line.startswith("|"):
                    break
                if set(cells[0]) <= set("-: "):
                    continue
                rows.append(cells)
    return rows


def read_table(path):
    layers = {}  # folder -> (layer, allowed layer names)
    for cells in table_rows(path, ["layer", "folder", "may include"]):
        name, folder = cells[0], cells[1].strip("`")
        allowed = {a.strip() for a in cells[2].split(",") if a.strip()}
        layers[folder] = (name, allowed)
    return layers


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    layers = read_table(os.path.join(root, "ARCHITECTURE.md"))
    if not layers:
        print("layers.py: no layer table in ARCHITECTURE.md")
        return 1
    names = {layer for layer, _ in layers.values()}
    errors = []
    for folder, (layer, allowed) in layers.items():
        for a in allowed - names:
            errors.append(f"ARCHITECTURE.md: layer {layer} may include unknown layer {a}")

    home = {}  # header basename -> layer
    files = []  # (path, layer)
    tops = sorted({folder.split("/")[0] for folder in layers})   # lib, include
    walked = [w for top in tops for w in os.walk(os.path.join(root, top))]
    for dirpath, _, filenames in walked:
        folder = os.path.relpath(dirpath, root)
        for fn in sorted(filenames):
            if not fn.endswith((".c", ".h")):
                continue
            path = os.path.join(folder, fn)
            if folder not in layers:
                errors.append(f"{path}: not in any folder of ARCHITECTURE.md's layer table")
                continue
            layer = layers[folder][0]
            files.append((path, layer))
            if fn.endswith(".h"):
                if fn in home or fn in GENERATED:
                    errors.append(f"{path}: header name {fn} is not unique in lib/")
                home[fn] = layer
    home.update(GENERATED)
    allowed_of = {layer: allowed | {layer} for layer, allowed in layers.values()}

    edges = 0
    include = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
    for path, layer in files:
        with open(os.path.join(root, path), encoding="utf-8") as f:
            for lineno, line in enumerate(f, 1):
                m = include.match(line)
                if not m:
                    continue
                target = m.group(1)
                base = os.path.basename(target)
                if target != base:
                    errors.append(f"{path}:{lineno}: include \"{target}\" names a folder; write \"{base}\"")
                if base not in home:
                    errors.append(f"{path}:{lineno}: \"{base}\" is not a header of lib/")
                    continue
                edges += 1
                if home[base] not in allowed_of[layer]:
                    errors.append(f"{path}:{lineno}: {layer} includes \"{base}\" of layer "
                                  f"{home[base]} (ARCHITECTURE.md: {layer} may include "
                                  f"{', '.join(sorted(allowed_of[layer] - {layer})) or 'nothing'})")
    # src/ (the flitter command) sees the library through flitter.h alone
    src = os.path.join(root, "src")
    own = {fn for fn in os.listdir(src) if fn.endswith(".h")} if os.path.isdir(src) else set()
    for fn in sorted(os.listdir(src)) if os.path.isdir(src) else []:
        if not fn.endswith((".c", ".h")):
            continue
        with open(os.path.join(src, fn), encoding="utf-8") as f:
            for lineno, line in enumerate(f, 1):
                m = include.match(line)
                if m and m.group(1) not in own and m.group(1) != "flitter.h":
                    errors.append(f"src/{fn}:{lineno}: includes \"{m.group(1)}\": the command "
                                  f"uses the library through flitter.h alone")
                elif m:
                    edges += 1
    # every source file has its place on the map
    with open(os.path.join(root, "ARCHITECTURE.md"), encoding="utf-8") as f:
        text = f.read()
    placed = 0
    for top in ("lib", "include", "src"):
        for dirpath, _, filenames in os.walk(os.path.join(root, top)):
            names = set(filenames)
            for fn in sorted(filenames):
                stem, ext = os.path.splitext(fn)
                if ext not in (".c", ".cpp", ".h"):
                    continue
                if ext == ".h" and (stem + ".c" in names or stem + ".cpp" in names):
                    continue
                if not re.search(r"(?<![\w.])" + re.escape(fn) + r"(?![\w])", text):
                    errors.append(f"{os.path.relpath(os.path.join(dirpath, fn), root)}: named nowhere in "
                                  f"ARCHITECTURE.md (say where it belongs and what it does)")
                else:
                    placed += 1
    for e in errors:
        print(e)
    if errors:
        print(f"layers.py: {len(errors)} violation(s)")
        return 1
    print(f"layers.py: {len(files)} files, {edges} includes, {len(layers)} layers, {placed} files placed: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
