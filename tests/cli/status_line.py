#!/usr/bin/env python3
"""status_line.py FLITTER SCRIPT: `flitter run` without --frames, with
stderr on a terminal (a pseudo-terminal), shows a live status line with
the frame number, frames per second and the clock; Ctrl-C (SIGINT) ends
the run with status 0 and a final newline."""
import os
import pty
import re
import select
import signal
import sys
import time

flitter, script = sys.argv[1], sys.argv[2]
pid, fd = pty.fork()
if pid == 0:
    os.execv(flitter, [flitter, "run", script])
out = b""
rx = re.compile(rb"\rframe (\d+)  \d+ frames/s  time (\d+\.\d\d)s ")
end = time.time() + 60
while len(rx.findall(out)) < 2:
    if time.time() > end:
        os.kill(pid, signal.SIGKILL)
        sys.exit(f"no status line: {out[-300:]!r}")
    r, _, _ = select.select([fd], [], [], 0.1)
    if r:
        out += os.read(fd, 4096)
frames = [int(f) for f, _ in rx.findall(out)]
if frames[1] <= frames[0]:
    sys.exit(f"the frame number does not advance: {frames}")
os.kill(pid, signal.SIGINT)
_, status = os.waitpid(pid, 0)
if not os.WIFEXITED(status) or os.WEXITSTATUS(status) != 0:
    sys.exit(f"status {status} after SIGINT")
sys.exit(0)
