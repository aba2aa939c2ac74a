#!/usr/bin/env python3
"""features.py FLITTER SCRIPT: terminal REPL features on a pseudo-terminal.
`_` is the last expression's result; `:set KEY VALUE` / `:unset KEY` edit
the state (expressions: the key a `!key` node would write); a node prints
with its attributes and children; a long :step shows a progress line,
stops at Ctrl-C with the state kept, and blanks the line out; a multi-line
block is one history entry, written to the history file as one and
replayed whole when recalled with the up arrow. The session runs through
ptysession.py, which waits on the output with generous time limits.
"""
import os
import re
import sys
import tempfile

from ptysession import Session

flitter, script = sys.argv[1], sys.argv[2]
scratch = tempfile.mkdtemp()
history = os.path.join(scratch, "history")
s = Session(flitter, [script], {"FLITTER_HISTORY": history,
                                "FLITTER_RECOVERY": os.path.join(scratch, "recovery.state")})

s.wait_for(r"flitter> ")
s.step(b"6*7\r", r"\n42\r?\n")
s.step(b"_+1\r", r"\n43\r?\n")                       # _ is the last result
s.step(b"let q=_*2\r", r"\nq = 86\r?\n")
s.step(b"_\r", r"\n43\r?\n")                         # a let leaves _ alone
s.step(b"!foo x=1;2\r", r"\n!foo x=1;2\r?\n")          # a node with its attributes
s.step(b"func mk()\r", r"\.\.\.> ", "")                   # a node with a child
s.step(b"    !a #t y=\"s\"\r        !b z=3\r\r", r"\nmk = \(func mk\)\r?\n")
s.step(b"mk()\r", r'\n!a #t y="s"\r?\n !b z=3\r?\n')
s.step(b":set :collapse 1\r", r"\n:collapse = 1\r?\n")
s.step(b"$(:collapse)\r", r"\n1\r?\n")
s.step(b":set (:p;2) 3*_\r", r"\n:p;2 = 3\r?\n")     # _ was 1: ($(:collapse))
s.step(b":unset :collapse\r", r"\n:collapse = null\r?\n")
s.step(b"$(:collapse)\r", r"\nnull\r?\n")
# a long :step: a progress line, Ctrl-C stops it between frames
s.out = b""
s.send(b":step 10000000\r")
s.wait_for(r"stepping: \d+ of 10000000 frames \(\d+%\), about \d+ s to go; Ctrl-C stops")
s.send(b"\x03")
s.wait_for(r"interrupted after (\d+) of 10000000 frames\r?\nframe \d+ time .*flitter> ")
if not re.search(rb"\r +\r", s.out):
    s.fail("the progress line was not blanked out")
s.step(b"$(:dish;:clock) > 1\r", r"\n1\r?\n")           # the state was kept
# a multi-line block: one history entry, recalled and replayed whole
s.step(b"func h(n)\r", r"\.\.\.> ", "")
s.step(b"    n*10+1\r\r", r"\nh = \(func h\)\r?\n")
s.step(b"h(4)\r", r"\n41\r?\n")
# libedit writes an entry's spaces and newlines as octal escapes
lines = [l.replace(b"\\040", b" ").replace(b"\\012", b"\n")
         for l in open(history, "rb").read().splitlines()]
entries = [l for l in lines if b"func h" in l]
if len(entries) != 1 or entries[0] != b"func h(n)\n    n*10+1":
    s.fail(f"the block is not one history entry: {lines!r}")
if any(l.strip() == b"n*10+1" for l in lines) or b":set :collapse 1" not in lines:
    s.fail(f"the block's second line is an entry of its own: {lines!r}")
s.step(b"let h=0\r", r"\nh = 0\r?\n")
s.step(b"\x1b[A\x1b[A\x1b[A\r", r"\nh = \(func h\)\r?\n")   # up 3 times: the block, replayed
s.step(b"h(5)\r", r"\n51\r?\n")
s.send(b":quit\r")
s.wait_exit(":quit")
for f in os.listdir(scratch):
    os.unlink(os.path.join(scratch, f))
os.rmdir(scratch)
sys.exit(0)
