#!/usr/bin/env python3
"""features.py FLITTER SCRIPT: terminal REPL features on a pseudo-terminal.
`_` is the last expression's result; `:set KEY VALUE` / `:unset KEY` edit
the state (expressions: the key a `!key` node would write); a node prints
with its attributes and children; a long :step shows a progress line,
stops at Ctrl-C with the state kept, and blanks the line out; a multi-line
block is one history entry, written to the history file as one and
replayed whole when recalled with the up arrow. Waits on the output, with
generous time limits, so a loaded machine only slows it.
"""
import os
import pty
import re
import select
import sys
import tempfile
import time

flitter, script = sys.argv[1], sys.argv[2]
scratch = tempfile.mkdtemp()
history = os.path.join(scratch, "history")
pid, fd = pty.fork()
if pid == 0:
    os.environ["FLITTER_HISTORY"] = history
    os.environ["FLITTER_RECOVERY"] = os.path.join(scratch, "recovery.state")
    os.environ["TERM"] = "dumb"
    os.execv(flitter, [flitter, "repl", script])

out = b""


def fail(msg):
    try:
        os.kill(pid, 9)
    except OSError:
        pass
    sys.stderr.write(f"{msg}\n--- session so far ---\n{out.decode(errors='replace')}\n")
    sys.exit(1)


def wait_for(pattern, limit=60.0):
    global out
    end = time.time() + limit
    rx = re.compile(pattern.encode(), re.S)
    while not rx.search(out):
        if time.time() > end:
            fail(f"timed out waiting for {pattern!r}")
        r, _, _ = select.select([fd], [], [], 0.1)
        if r:
            try:
                data = os.read(fd, 4096)
            except OSError:
                data = b""
            if not data:
                fail(f"session ended while waiting for {pattern!r}")
            out += data


def step(line, pattern, prompt=r".*flitter> "):
    """Type [line], wait for [pattern] then the next prompt."""
    global out
    out = b""
    os.write(fd, line)
    wait_for(pattern + prompt)


wait_for(r"flitter> ")
step(b"6*7\r", r"\n42\r?\n")
step(b"_+1\r", r"\n43\r?\n")                       # _ is the last result
step(b"let q=_*2\r", r"\nq = 86\r?\n")
step(b"_\r", r"\n43\r?\n")                         # a let leaves _ alone
step(b"!foo x=1;2\r", r"\n!foo x=1;2\r?\n")          # a node with its attributes
step(b"func mk()\r", r"\.\.\.> ", "")                   # a node with a child
step(b"    !a #t y=\"s\"\r        !b z=3\r\r", r"\nmk = \(func mk\)\r?\n")
step(b"mk()\r", r'\n!a #t y="s"\r?\n !b z=3\r?\n')
step(b":set :collapse 1\r", r"\n:collapse = 1\r?\n")
step(b"$(:collapse)\r", r"\n1\r?\n")
step(b":set (:p;2) 3*_\r", r"\n:p;2 = 3\r?\n")     # _ was 1: ($(:collapse))
step(b":unset :collapse\r", r"\n:collapse = null\r?\n")
step(b"$(:collapse)\r", r"\nnull\r?\n")
# a long :step: a progress line, Ctrl-C stops it between frames
out = b""
os.write(fd, b":step 10000000\r")
wait_for(r"stepping: \d+ of 10000000 frames \(\d+%\), about \d+ s to go; Ctrl-C stops")
os.write(fd, b"\x03")
wait_for(r"interrupted after (\d+) of 10000000 frames\r?\nframe \d+ time .*flitter> ")
if not re.search(rb"\r +\r", out):
    fail("the progress line was not blanked out")
step(b"$(:dish;:clock) > 1\r", r"\n1\r?\n")           # the state was kept
# a multi-line block: one history entry, recalled and replayed whole
step(b"func h(n)\r", r"\.\.\.> ", "")
step(b"    n*10+1\r\r", r"\nh = \(func h\)\r?\n")
step(b"h(4)\r", r"\n41\r?\n")
# libedit writes an entry's spaces and newlines as octal escapes
lines = [l.replace(b"\\040", b" ").replace(b"\\012", b"\n")
         for l in open(history, "rb").read().splitlines()]
entries = [l for l in lines if b"func h" in l]
if len(entries) != 1 or entries[0] != b"func h(n)\n    n*10+1":
    fail(f"the block is not one history entry: {lines!r}")
if any(l.strip() == b"n*10+1" for l in lines) or b":set :collapse 1" not in lines:
    fail(f"the block's second line is an entry of its own: {lines!r}")
step(b"let h=0\r", r"\nh = 0\r?\n")
step(b"\x1b[A\x1b[A\x1b[A\r", r"\nh = \(func h\)\r?\n")   # up 3 times: the block, replayed
step(b"h(5)\r", r"\n51\r?\n")
out = b""
os.write(fd, b":quit\r")
end = time.time() + 30
while True:
    done, status = os.waitpid(pid, os.WNOHANG)
    if done:
        break
    if time.time() > end:
        fail(":quit did not end the session")
    try:
        r, _, _ = select.select([fd], [], [], 0.1)
        if r:
            os.read(fd, 4096)
    except OSError:
        pass
if not os.WIFEXITED(status) or os.WEXITSTATUS(status) != 0:
    fail(f"exit status {status}")
for f in os.listdir(scratch):
    os.unlink(os.path.join(scratch, f))
os.rmdir(scratch)
sys.exit(0)
