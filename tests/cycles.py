#!/usr/bin/env python3
"""cycles.py: check that the library's files call each other only down the map.

usage: cycles.py REPO_ROOT LIBFLITTER_INTERNAL.a

Reads which functions each object of the static library defines and which
it calls (`nm`), and from that which source files of lib/ call into which.
Two files that call into each other, directly or around a longer circle,
are allowed only inside one room of ARCHITECTURE.md's "Files that call
each other" list (a row names the files by pattern, e.g. `physics/*.c`).
Any other circle (the runtime calling a file that calls the runtime back,
say) is printed with the calls that close it, and the check exits 1.
Exits 0 with a summary when every circle lies in a listed room.
"""
import fnmatch
import os
import re
import subprocess
import sys

from layers import table_rows   # tests/layers.py, beside this file


def read_rooms(path):
    """(patterns, reason) of each row of the "files that call each other" table."""
    return [(re.findall(r"`([^`]+)`", cells[0]), cells[1])
            for cells in table_rows(path, ["files that call each other", "why"])]


def modules(root, archive):
    """object name in the archive -> source path relative to lib/"""
    sources = {}
    for dirpath, _, files in os.walk(os.path.join(root, "lib")):
        for fn in files:
            if fn.endswith((".c", ".cpp")):
                rel = os.path.relpath(os.path.join(dirpath, fn), os.path.join(root, "lib"))
                sources[rel.replace("/", "_") + ".o"] = rel
    return sources


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    root, archive = sys.argv[1], sys.argv[2]
    rooms = read_rooms(os.path.join(root, "ARCHITECTURE.md"))
    if not rooms:
        print("cycles.py: no 'files that call each other' table in ARCHITECTURE.md")
        return 1
    sources = modules(root, archive)
    out = subprocess.run(["nm", "-A", archive], capture_output=True, text=True, check=True).stdout
    defined, called = {}, {}
    for line in out.splitlines():
        m = re.match(r"[^:]*:([^:]+):\s*(?:[0-9a-fA-F]+\s+)?([A-Za-z])\s+(\S+)$", line)
        if not m:
            continue
        obj, kind, sym = m.groups()
        # meson names an object by its source's path ('/' as '_'); the
        # grammar's generated files are syntax's
        obj = obj.rsplit("/", 1)[-1]   # a thin archive names its members by path
        name = sources.get(obj)
        if name is None:
            name = "syntax/parser.c (generated)" if "grammar" in obj else obj
        if kind == "U":
            called.setdefault(name, set()).add(sym)
        elif kind in "TDBRCV":
            defined[sym] = name
    edges = {m: {} for m in set(called) | set(defined.values())}
    for m, syms in called.items():
        for s in syms:
            d = defined.get(s)
            if d and d != m:
                edges[m].setdefault(d, []).append(s)

    # Tarjan's strongly connected components, iteratively
    index, low, stack, on, comps, counter = {}, {}, [], set(), [], [0]
    for start in sorted(edges):
        if start in index:
            continue
        work = [(start, iter(sorted(edges[start])))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges[w]))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    x = stack.pop()
                    on.discard(x)
                    comp.append(x)
                    if x == v:
                        break
                if len(comp) > 1:
                    comps.append(sorted(comp))

    def room_of(f):
        for i, (pats, _) in enumerate(rooms):
            if any(fnmatch.fnmatch(f, p) for p in pats):
                return i
        return None

    errors = 0
    for comp in comps:
        homes = {room_of(f) for f in comp}
        if len(homes) == 1 and None not in homes:
            continue
        errors += 1
        print(f"cycles.py: these files call each other outside a room of ARCHITECTURE.md: {', '.join(comp)}")
        inside = set(comp)
        for f in comp:
            for d, syms in sorted(edges[f].items()):
                if d in inside and (room_of(f) is None or room_of(d) != room_of(f)):
                    print(f"    {f} -> {d}: {' '.join(sorted(syms)[:6])}")
    if errors:
        return 1
    print(f"cycles.py: {len(edges)} files, {sum(len(e) for e in edges.values())} calls between files; "
          f"{len(comps)} circles, each inside one of {len(rooms)} rooms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
