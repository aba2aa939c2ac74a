#!/usr/bin/env python3
"""spec_refs.py ROOT: every specification a source comment cites resolves
inside the repository.

In the sources of lib/, src/, grammar/ and python/, every `NAME.md` must be
a file of the repository (docs/spec/NAME.md, or the path as written from the
root, or a file of that name anywhere in it), unless the text names Flitter
within the 120 characters before it (a citation of Flitter's own documents,
the specification for rendering: "Flitter docs/shaders.md"). Every
"LANGUAGE.md §N.N", "PHYSICS-ENGINE.md §N", "FORMATS.md §N" and
"COUNTERS.md §N" must name a section heading of that document in docs/spec/.
Prints each failure as FILE:LINE: message and exits 1; 0 when all resolve."""
import os
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else "."
EXTS = (".c", ".h", ".cpp", ".y", ".re", ".py", ".glsl", ".frag", ".vert", ".sh", ".map")
repo_md = {}
for d, dirs, files in os.walk(root):
    dirs[:] = [x for x in dirs if not x.startswith(".") and not x.startswith("build") and x != "subprojects"]
    for f in files:
        if f.endswith(".md"):
            repo_md.setdefault(f, []).append(os.path.relpath(os.path.join(d, f), root))

def sections(name):
    """The section numbers of docs/spec/NAME's headings (`## 4.` / `### 4.17`)."""
    path = os.path.join(root, "docs", "spec", name)
    if not os.path.exists(path):
        return set()
    found = set()
    for line in open(path, encoding="utf-8"):
        m = re.match(r"#+\s+(?:Appendix\s+)?([0-9A-Z]+(?:\.[0-9]+)*)\.?\s", line)
        if m:
            found.add(m.group(1))
    return found

secs = {n: sections(n) for n in ("LANGUAGE.md", "PHYSICS-ENGINE.md", "FORMATS.md", "COUNTERS.md")}
fail = 0
for top in ("lib", "src", "grammar", "python"):
    for d, dirs, files in os.walk(os.path.join(root, top)):
        for f in files:
            if not f.endswith(EXTS):
                continue
            path = os.path.join(d, f)
            text = open(path, encoding="utf-8", errors="replace").read()
            for m in re.finditer(r"([A-Za-z0-9_./-]*?)([A-Za-z0-9_-]+\.md)\b", text):
                name, full = m.group(2), m.group(1) + m.group(2)
                line = text.count("\n", 0, m.start()) + 1
                where = f"{os.path.relpath(path, root)}:{line}"
                before = text[max(0, m.start() - 120):m.start()]
                if "Flitter" in before and not os.path.exists(os.path.join(root, "docs", "spec", name)):
                    continue
                if not (os.path.exists(os.path.join(root, full)) or name in repo_md):
                    print(f"{where}: {full} is not in the repository")
                    fail = 1
                    continue
                if name in secs:
                    after = text[m.end():m.end() + 40]
                    for s in re.findall(r"^ §([0-9A-Z]+(?:\.[0-9]+)*)", after):
                        if s.rstrip(".") not in secs[name]:
                            print(f"{where}: {name} has no section §{s}")
                            fail = 1
sys.exit(fail)
