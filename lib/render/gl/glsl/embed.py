#!/usr/bin/env python3
"""embed.py: make glsl_sources.c, the GLSL files of this folder as C strings.

usage: embed.py OUTPUT FILE...

glsl_library(NAME) (glsl_library.h) returns the text of the file named NAME
(its base name), or NULL.
"""
import os
import sys


def c_string(text):
    out = []
    for line in text.splitlines(keepends=True):
        esc = line.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
        out.append(f'    "{esc}"')
    return "\n".join(out) if out else '    ""'


def main():
    output, files = sys.argv[1], sorted(sys.argv[2:], key=os.path.basename)
    parts = ["/* glsl_sources.c: made by glsl/embed.py from lib/render/gl/glsl; do not edit. */",
             '#include "glsl_library.h"', "", "#include <string.h>", "",
             "static const struct { const char *name, *text; } files[] = {"]
    for path in files:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        parts.append(f'  {{"{os.path.basename(path)}",\n{c_string(text)}}},')
    parts += ["};", "",
              "const char *glsl_library(const char *name)",
              "{",
              "    for (size_t i = 0; i < sizeof files / sizeof *files; i++)",
              "        if (strcmp(files[i].name, name) == 0) return files[i].text;",
              "    return NULL;",
              "}", ""]
    with open(output, "w", encoding="utf-8") as f:
        f.write("\n".join(parts))


if __name__ == "__main__":
    main()
