#!/usr/bin/env python3
"""ctrlc.py FLITTER SCRIPT: a terminal REPL session on a pseudo-terminal.
Ctrl-C interrupts a long :step between frames and returns to the prompt
with the session intact; Ctrl-C stops a line that runs for ever (an
interrupted evaluation) and cuts the output of a long result; Ctrl-C drops
a half-typed line; a second Ctrl-C at
an empty prompt asks before quitting ("n" goes on with the state intact,
"y" saves the state to the recovery file, says where, and ends the session
with status 0; the file restores the frame); UTF-8 typing comes through
whole; Tab completes a built-in function name. Waits on the output (not on
fixed sleeps) with generous time limits, so a loaded machine only slows it.
"""
import os
import pty
import re
import select
import sys
import time

flitter, script = sys.argv[1], sys.argv[2]
import tempfile

scratch = tempfile.mkdtemp()
recovery = os.path.join(scratch, "recovery.state")
pid, fd = pty.fork()
if pid == 0:
    os.environ["FLITTER_HISTORY"] = os.devnull
    os.environ["FLITTER_RECOVERY"] = recovery
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
    """Read until the output after the last mark matches [pattern]."""
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


def send(data):
    os.write(fd, data)


wait_for(r"flitter> ")
send(b":step 10000000\r")
wait_for(r":step 10000000\r?\n")
time.sleep(0.3)                      # let a few frames run
send(b"\x03")
wait_for(r"interrupted after (\d+) of 10000000 frames\r?\nframe (\d+) time")
m = re.search(rb"interrupted after (\d+) of 10000000 frames\r?\nframe (\d+) time", out)
if int(m.group(2)) != int(m.group(1)) - 1:
    fail("the frame printed is not the last one stepped")
wait_for(r"frame \d+ time [^\n]*\n.*flitter> ")
# each step waits for the prompt that follows its output before going on,
# so that typing never races the REPL
out = b""
send(b"$(:dish;:clock) > 0\r")        # the session (and its state) survived
wait_for(r"\n1\r?\n.*flitter> ")
out = b""
send(b"func g(n)\r")                  # a line that runs for ever: 2^60 calls
send(b"    0 if n < 1 else g(n-1) + g(n-1)\r")
send(b"\r")
wait_for(r"g = \(func g\)\r?\n.*flitter> ")
out = b""
send(b"g(60)\r")
wait_for(r"g\(60\)\r?\n")
time.sleep(0.5)
send(b"\x03")                         # Ctrl-C stops it, nothing printed
wait_for(r"<repl>: error: interrupted\r?\n.*flitter> ")
out = b""
send(b"..2**21\r")                    # a long result: Ctrl-C cuts its output
wait_for(r"0;1;2;3;4;5")
send(b"\x03")
wait_for(r"\(output interrupted\)\r?\n.*flitter> ")
out = b""
send(b"(1+")                          # a half-typed line, then Ctrl-C
wait_for(r"\(1\+")
send(b"\x03")
wait_for(r"flitter> ")
out = b""
send(b"6*7\r")
wait_for(r"\n42\r?\n.*flitter> ")
out = b""
send(b"hyp\t")                        # Tab completes a built-in function name
wait_for(r"hypot")
send(b"(3;4)\r")
wait_for(r"\n5\r?\n.*flitter> ")
out = b""
send('"h\u00e9\u2192"\r'.encode())     # non-ASCII typing survives the reader
wait_for('\n"h\u00e9\u2192"\r?\n.*flitter> ')
send(b"\x03")
wait_for(r"Ctrl-C again")
out = b""
send(b"\x03")                         # a second Ctrl-C asks first; "n" goes on
wait_for(r"Quit\? .*\[y/N\] ")
send(b"n\r")
wait_for(r"\(going on\)\r?\n.*flitter> ")
out = b""
send(b"$(:dish;:clock) > 0\r")        # the session and its state are still there
wait_for(r"\n1\r?\n.*flitter> ")
out = b""
send(b"\x03")
wait_for(r"Ctrl-C again")
send(b"\x03")                         # yes: the state goes to the recovery file
wait_for(r"Quit\? .*\[y/N\] ")
send(b"y\r")
wait_for(r"state saved to " + re.escape(recovery) + r" \(frame (\d+);")
end = time.time() + 30
while True:
    done, status = os.waitpid(pid, os.WNOHANG)
    if done:
        break
    if time.time() > end:
        fail("a second Ctrl-C at an empty prompt did not end the session")
    try:
        r, _, _ = select.select([fd], [], [], 0.1)
        if r:                         # a read without output would block
            os.read(fd, 4096)
    except OSError:
        pass
if not os.WIFEXITED(status) or os.WEXITSTATUS(status) != 0:
    fail(f"exit status {status}")
# the recovery file restores the session's state and clock
frame = int(re.search(rb"state saved to .* \(frame (\d+);", out).group(1))
import subprocess
got = subprocess.run([flitter, "repl", script], input=f":restore {recovery}\n$(:dish;:clock) > 0\n",
                     capture_output=True, text=True, timeout=120)
os.unlink(recovery)
os.rmdir(scratch)
if got.returncode != 0 or f"(frame {frame})" not in got.stdout or not got.stdout.endswith("\n1\n"):
    fail(f"the recovery file does not restore frame {frame}: {got.stdout!r} {got.stderr!r}")
sys.exit(0)
