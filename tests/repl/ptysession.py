"""ptysession.py: a `flitter repl` session on a pseudo-terminal, for the
REPL's terminal tests (ctrlc.py, features.py). It waits on the output (not
on fixed sleeps) with generous time limits, so a loaded machine only slows
a test; on any failure it kills the session and prints what it said.
"""
import os
import pty
import re
import select
import sys
import time


class Session:
    """`FLITTER repl ARGS...` on a pseudo-terminal with TERM=dumb and the
    environment variables [env] set; [out] is the output read since it was
    last set to b""."""

    def __init__(self, flitter, args, env):
        self.out = b""
        self.pid, self.fd = pty.fork()
        if self.pid == 0:
            os.environ.update(env)
            os.environ["TERM"] = "dumb"
            os.execv(flitter, [flitter, "repl"] + list(args))

    def fail(self, msg):
        """Kill the session, print [msg] and the output so far, exit 1."""
        try:
            os.kill(self.pid, 9)
        except OSError:
            pass
        sys.stderr.write(f"{msg}\n--- session so far ---\n{self.out.decode(errors='replace')}\n")
        sys.exit(1)

    def send(self, data):
        """Type [data] (bytes)."""
        os.write(self.fd, data)

    def wait_for(self, pattern, limit=60.0):
        """Read until [out] matches [pattern] (a str regex, dot matching
        newlines); fail after [limit] seconds or when the session ends."""
        end = time.time() + limit
        rx = re.compile(pattern.encode(), re.S)
        while not rx.search(self.out):
            if time.time() > end:
                self.fail(f"timed out waiting for {pattern!r}")
            r, _, _ = select.select([self.fd], [], [], 0.1)
            if r:
                try:
                    data = os.read(self.fd, 4096)
                except OSError:
                    data = b""
                if not data:
                    self.fail(f"session ended while waiting for {pattern!r}")
                self.out += data

    def step(self, line, pattern, prompt=r".*flitter> "):
        """Type [line] with [out] cleared, wait for [pattern] then the next
        prompt, so that typing never races the REPL."""
        self.out = b""
        self.send(line)
        self.wait_for(pattern + prompt)

    def wait_exit(self, what, limit=30.0):
        """Wait for the session to end (draining its output, since a full
        pseudo-terminal would hold it up); fail unless it exits with status
        0 within [limit] seconds ([what] names the cause in the message)."""
        end = time.time() + limit
        while True:
            done, status = os.waitpid(self.pid, os.WNOHANG)
            if done:
                break
            if time.time() > end:
                self.fail(f"{what} did not end the session")
            try:
                r, _, _ = select.select([self.fd], [], [], 0.1)
                if r:
                    self.out += os.read(self.fd, 4096)
            except OSError:
                pass
        if not os.WIFEXITED(status) or os.WEXITSTATUS(status) != 0:
            self.fail(f"exit status {status}")
