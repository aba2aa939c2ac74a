#!/usr/bin/env python3
"""ctrlc.py FLITTER SCRIPT: a terminal REPL session on a pseudo-terminal.
Ctrl-C interrupts a long :step between frames and returns to the prompt
with the session intact; Ctrl-C stops a line that runs for ever (an
interrupted evaluation) and cuts the output of a long result; Ctrl-C drops
a half-typed line; a second Ctrl-C at
an empty prompt asks before quitting ("n" goes on with the state intact,
"y" saves the state to the recovery file, says where, and ends the session
with status 0; the file restores the frame); UTF-8 typing comes through
whole; Tab completes a built-in function name. The session runs through
ptysession.py, which waits on the output with generous time limits.
"""
import os
import re
import subprocess
import sys
import tempfile
import time

from ptysession import Session

flitter, script = sys.argv[1], sys.argv[2]
scratch = tempfile.mkdtemp()
recovery = os.path.join(scratch, "recovery.state")
s = Session(flitter, [script], {"FLITTER_HISTORY": os.devnull, "FLITTER_RECOVERY": recovery})

s.wait_for(r"flitter> ")
s.send(b":step 10000000\r")
s.wait_for(r":step 10000000\r?\n")
time.sleep(0.3)                      # let a few frames run
s.send(b"\x03")
s.wait_for(r"interrupted after (\d+) of 10000000 frames\r?\nframe (\d+) time")
m = re.search(rb"interrupted after (\d+) of 10000000 frames\r?\nframe (\d+) time", s.out)
if int(m.group(2)) != int(m.group(1)) - 1:
    s.fail("the frame printed is not the last one stepped")
s.wait_for(r"frame \d+ time [^\n]*\n.*flitter> ")
# each step waits for the prompt that follows its output before going on,
# so that typing never races the REPL
s.out = b""
s.send(b"$(:dish;:clock) > 0\r")        # the session (and its state) survived
s.wait_for(r"\n1\r?\n.*flitter> ")
s.out = b""
s.send(b"func g(n)\r")                  # a line that runs for ever: 2^60 calls
s.send(b"    0 if n < 1 else g(n-1) + g(n-1)\r")
s.send(b"\r")
s.wait_for(r"g = \(func g\)\r?\n.*flitter> ")
s.out = b""
s.send(b"g(60)\r")
s.wait_for(r"g\(60\)\r?\n")
time.sleep(0.5)
s.send(b"\x03")                         # Ctrl-C stops it, nothing printed
s.wait_for(r"<repl>: error: interrupted\r?\n.*flitter> ")
s.out = b""
s.send(b"..2**21\r")                    # a long result: Ctrl-C cuts its output
s.wait_for(r"0;1;2;3;4;5")
s.send(b"\x03")
s.wait_for(r"\(output interrupted\)\r?\n.*flitter> ")
s.out = b""
s.send(b"(1+")                          # a half-typed line, then Ctrl-C
s.wait_for(r"\(1\+")
s.send(b"\x03")
s.wait_for(r"flitter> ")
s.out = b""
s.send(b"6*7\r")
s.wait_for(r"\n42\r?\n.*flitter> ")
s.out = b""
s.send(b"hyp\t")                        # Tab completes a built-in function name
s.wait_for(r"hypot")
s.send(b"(3;4)\r")
s.wait_for(r"\n5\r?\n.*flitter> ")
s.out = b""
s.send('"h\u00e9\u2192"\r'.encode())     # non-ASCII typing survives the reader
s.wait_for('\n"h\u00e9\u2192"\r?\n.*flitter> ')
s.send(b"\x03")
s.wait_for(r"Ctrl-C again")
s.out = b""
s.send(b"\x03")                         # a second Ctrl-C asks first; "n" goes on
s.wait_for(r"Quit\? .*\[y/N\] ")
s.send(b"n\r")
s.wait_for(r"\(going on\)\r?\n.*flitter> ")
s.out = b""
s.send(b"$(:dish;:clock) > 0\r")        # the session and its state are still there
s.wait_for(r"\n1\r?\n.*flitter> ")
s.out = b""
s.send(b"\x03")
s.wait_for(r"Ctrl-C again")
s.send(b"\x03")                         # yes: the state goes to the recovery file
s.wait_for(r"Quit\? .*\[y/N\] ")
s.send(b"y\r")
s.wait_for(r"state saved to " + re.escape(recovery) + r" \(frame (\d+);")
s.wait_exit("a second Ctrl-C at an empty prompt")
# the recovery file restores the session's state and clock
frame = int(re.search(rb"state saved to .* \(frame (\d+);", s.out).group(1))
got = subprocess.run([flitter, "repl", script], input=f":restore {recovery}\n$(:dish;:clock) > 0\n",
                     capture_output=True, text=True, timeout=120)
os.unlink(recovery)
os.rmdir(scratch)
if got.returncode != 0 or f"(frame {frame})" not in got.stdout or not got.stdout.endswith("\n1\n"):
    s.fail(f"the recovery file does not restore frame {frame}: {got.stdout!r} {got.stderr!r}")
sys.exit(0)
