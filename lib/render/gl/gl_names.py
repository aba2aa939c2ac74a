#!/usr/bin/env python3
"""gl_names.py: make gl_names.h from gl_lib.h's FL_GL_POINTERS list.

usage: gl_names.py GL_LIB_H OUTPUT

For each name of the list, gl_names.h undefines epoxy's macro of that name
and defines the name as a call through the address of epoxy's pointer kept
in the library's table (gl_lib.h says why), so adding a name to the list is
all that a new GL or EGL function needs.
"""
import re
import sys


def main():
    text = open(sys.argv[1], encoding="utf-8").read()
    m = re.search(r"#define FL_GL_POINTERS\(X\)((?:[^\n]*\\\n)*[^\n]*\n)", text)
    if not m:
        sys.exit("gl_names.py: no FL_GL_POINTERS list in " + sys.argv[1])
    names = re.findall(r"X\((\w+)\)", m.group(1))
    out = ["/* gl_names.h: made by gl_names.py from gl_lib.h; do not edit. */"]
    for name in names:
        out.append(f"#undef {name}\n#define {name} (*FL_GL->p_{name})")
    with open(sys.argv[2], "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
