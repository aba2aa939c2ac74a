"""flitter_c: Flitter scripts and their !physics from Python, over libflitter.

Only the public C interface (include/flitter.h) is used, through cffi in API
mode. A ``Simulation`` owns one runtime; several may live side by side in
one process (nothing is global), each used by one thread at a time (a lock
per simulation enforces it). The GIL is released inside every library call,
so stepping one simulation does not stop other Python threads.

    sim = flitter_c.load("dish.fl", defines={"N": 200}, simplify=True, fps=60)
    sim.step(120)
    ids, pos = sim.positions("dish")     # pos: float64 array, shape (n, D)

Units: ``time`` in seconds of the frame clock (a frame lasts 1/fps s);
positions in the system's own units; velocities in those units per second
of the system's clock.
"""
from __future__ import annotations

import logging
import os
import re
import threading
from typing import Any, Dict, Iterator, List, Mapping, MutableMapping, Optional, Tuple

import numpy as np

from ._flitter_cffi import ffi, lib
from ._values import Symbol, define_text, key_text, number_text, parse_id, parse_value

__all__ = ["FlitterError", "Node", "Simulation", "State", "Symbol", "load", "version"]

log = logging.getLogger("flitter_c")
_LEVELS = {0: logging.ERROR, 1: logging.WARNING, 2: logging.DEBUG}

_LOCATION = re.compile(r"^(?P<path>.*?):(?P<line>\d+):(?P<col>\d+): error: (?P<msg>.*)$", re.M)


def version() -> str:
    """The library's version, "MAJOR.MINOR.PATCH"."""
    return ffi.string(lib.fl_version()).decode()


class FlitterError(Exception):
    """A failed library call. For script errors, ``path``, ``line`` and
    ``col`` (1-based) give the location and ``message`` the bare message;
    ``str(err)`` is the library's whole text (location, source line,
    caret)."""

    def __init__(self, text: str):
        super().__init__(text.rstrip("\n"))
        self.text = text
        m = _LOCATION.search(text)
        self.path: Optional[str] = m.group("path") if m else None
        self.line: Optional[int] = int(m.group("line")) if m else None
        self.col: Optional[int] = int(m.group("col")) if m else None
        self.message: str = m.group("msg") if m else text.strip()


class Node:
    """One node of a frame's tree: ``kind`` (without the ``!``), ``attrs``
    (name → value as ``State`` converts them) and ``children``."""

    __slots__ = ("kind", "attrs", "children")

    def __init__(self, kind: str, attrs: Dict[str, Any], children: List["Node"]):
        self.kind, self.attrs, self.children = kind, attrs, children

    def __repr__(self) -> str:
        return f"Node({self.kind!r}, {len(self.attrs)} attrs, {len(self.children)} children)"


# {=====================================================================
# Callbacks: ctx is a cffi handle to a Python list or callable
# =====================================================================

@ffi.def_extern()
def _py_log(ctx, kind, line):
    sim = ffi.from_handle(ctx)
    text = ffi.string(line).decode("utf-8", "replace")
    sim.messages.append((kind, text))
    log.log(_LEVELS.get(kind, logging.INFO), "%s", text)


@ffi.def_extern()
def _py_write(ctx, text, n):
    ffi.from_handle(ctx).append(ffi.unpack(text, n))


@ffi.def_extern()
def _py_state(ctx, key, value):
    ffi.from_handle(ctx).append((ffi.string(key).decode("utf-8", "surrogateescape"),
                                 ffi.string(value).decode("utf-8", "surrogateescape")))
    return 0


@ffi.def_extern()
def _py_particle(ctx, id_text, position, velocity, dims):
    out = ffi.from_handle(ctx)
    out[0].append(ffi.string(id_text).decode("utf-8", "surrogateescape"))
    out[1].append(ffi.unpack(position, dims))
    out[2].append(ffi.unpack(velocity, dims))
    return 0


def _c(text: Any) -> bytes:
    """Text for the C interface, NUL-terminated there: a NUL inside would cut
    it short, so it is refused as Python's own os functions refuse it."""
    if isinstance(text, bytes):   # a path as bytes, as os functions take it
        b = text
    elif isinstance(text, os.PathLike):
        b = os.fsencode(text)
    else:
        b = text.encode("utf-8", "surrogateescape")
    if b"\0" in b:
        raise ValueError("embedded null byte")
    return b


def _define_numbers(value: Any) -> Optional[np.ndarray]:
    """``value`` as float64 numbers when it is a number, a bool or a
    (nested) sequence or array of them; None when any part is text (str,
    Symbol), which goes through Flitter's reading of define text."""
    if isinstance(value, str):
        return None
    if isinstance(value, (list, tuple)) and any(_define_numbers(v) is None for v in value):
        return None
    if isinstance(value, np.ndarray) and value.dtype.kind not in "biuf":
        return None
    return np.ascontiguousarray(np.atleast_1d(np.asarray(value, dtype=np.float64)).ravel())


def _tree_tokens(line: str) -> List[str]:
    """Split a tree-dump line into words, keeping quoted strings whole."""
    out, i, n = [], 0, len(line)
    while i < n:
        if line[i] == " ":
            i += 1
            continue
        j, quoted = i, False
        while j < n and (quoted or line[j] != " "):
            if line[j] == "\\" and quoted:
                j += 1
            elif line[j] == '"':
                quoted = not quoted
            j += 1
        out.append(line[i:j])
        i = j
    return out


class State(MutableMapping):
    """The state dictionary as a mapping. Keys are value text as the library
    parses it (``":dish;0"``; strings unquoted) or tuples of parts
    (``(Symbol("dish"), 0)``). Values read: None never (a missing key raises
    KeyError), a float, a float64 array of shape (n,), a Symbol/str, or a
    tuple of mixed parts. Values written: numbers and arrays exactly; a
    Symbol as a symbol; a str as a string (ValueError when the text would
    not read back as that one string, e.g. ``"1"`` or ``"a;b"``); None or
    ``del`` deletes. Iteration follows the state dump's key order."""

    def __init__(self, sim: "Simulation"):
        self._sim = sim

    def _get_text(self, key: Any) -> Optional[str]:
        rt, k = self._sim._rt, _c(key_text(key))
        with self._sim._lock:
            n = lib.fl_state_get(rt, k, ffi.NULL, 0)
            if n < 0:
                return None
            buf = ffi.new("char[]", n + 1)
            lib.fl_state_get(rt, k, buf, n + 1)
        return ffi.string(buf).decode("utf-8", "surrogateescape")

    def __getitem__(self, key: Any) -> Any:
        text = self._get_text(key)
        if text is None:
            raise KeyError(key)
        return parse_value(text)

    def __setitem__(self, key: Any, value: Any) -> None:
        sim, k = self._sim, _c(key_text(key))
        if value is None:
            with sim._lock:
                lib.fl_state_set(sim._rt, k, b"")
            return
        if isinstance(value, str):
            text = ":" + value if isinstance(value, Symbol) else value
            with sim._lock:   # set, read back and undo as one step
                rc = lib.fl_state_set(sim._rt, k, _c(text))
                if rc != 0:
                    raise KeyError(key)
                back = self[key]
                if back != value or isinstance(back, Symbol) != isinstance(value, Symbol):
                    lib.fl_state_set(sim._rt, k, b"")
                    raise ValueError(f"{value!r} cannot be stored as one {'symbol' if isinstance(value, Symbol) else 'string'} (value text would read as {back!r})")
            return
        arr = np.ascontiguousarray(np.atleast_1d(np.asarray(value, dtype=np.float64)).ravel())
        with sim._lock:
            rc = lib.fl_state_set_numbers(sim._rt, k, ffi.cast("const double *", arr.ctypes.data), arr.size)
        if rc != 0:
            raise KeyError(key)

    def __delitem__(self, key: Any) -> None:
        with self._sim._lock:   # the test and the delete as one step
            if self._get_text(key) is None:
                raise KeyError(key)
            self[key] = None

    # The mapping's compound methods read and then write; each holds the
    # simulation's (reentrant) lock throughout, so that another thread's
    # load_state or del cannot come between (pop with a default never
    # raises KeyError).
    def pop(self, key: Any, *default: Any) -> Any:
        with self._sim._lock:
            return super().pop(key, *default)

    def popitem(self) -> Tuple[Any, Any]:
        with self._sim._lock:
            return super().popitem()

    def setdefault(self, key: Any, default: Any = None) -> Any:
        with self._sim._lock:
            return super().setdefault(key, default)

    def update(self, *args: Any, **kwargs: Any) -> None:
        with self._sim._lock:
            super().update(*args, **kwargs)

    def clear(self) -> None:
        with self._sim._lock:
            super().clear()

    def items_text(self) -> List[Tuple[str, str]]:
        """Every entry as (key text, value text), in state-dump order; key
        text as the dump prints it (strings quoted)."""
        out: List[Tuple[str, str]] = []
        h = ffi.new_handle(out)
        with self._sim._lock:
            lib.fl_state_iterate(self._sim._rt, lib._py_state, h)
        return out

    def __iter__(self) -> Iterator[str]:
        for k, _ in self.items_text():
            # the dump's text, with string parts unquoted (the key text the
            # library parses)
            yield k if '"' not in k else key_text(tuple(_split(k)))

    def __len__(self) -> int:
        with self._sim._lock:
            return int(lib.fl_state_count(self._sim._rt))


def _split(text: str):
    from ._values import split_parts
    return split_parts(text)


class Simulation:
    """One Flitter runtime with a loaded script. Create with ``load()``."""

    def __init__(self, fps: float = 60.0, simplify: bool = True, physics: str = "documented",
                 threads: int = 0, realtime: bool = False):
        self._lock = threading.RLock()
        self.messages: List[Tuple[int, str]] = []
        """Log lines as (kind, text): 0 error, 1 warning, 2 debug()."""
        self._handle = ffi.new_handle(self)
        o = ffi.new("fl_options *", lib.fl_default_options())
        o.fps = float(fps)
        o.no_simplify = not simplify
        o.threads = int(threads)
        o.realtime = bool(realtime)
        mode = ffi.new("int *")
        if not lib.fl_parse_physics(physics.encode(), mode):
            raise ValueError(f"physics must be 'documented' or 'upstream', not {physics!r}")
        o.physics = mode[0]
        o.log = lib._py_log
        o.ctx = self._handle
        self._rt = ffi.gc(lib.fl_new(o), lib.fl_free)
        self.state = State(self)
        """The state dictionary (a ``State`` mapping)."""

    def _error(self) -> FlitterError:
        return FlitterError(ffi.string(lib.fl_error(self._rt)).decode("utf-8", "replace"))

    def define(self, name: str, value: Any) -> None:
        """Bind ``name`` to ``value`` for every frame (as ``-D``); takes
        effect at the next ``load``. Numbers, bools and sequences or arrays
        of them are bound exactly as numbers (-3 is -3), None as null, a
        Symbol as that symbol; a str is read as ``-D NAME=VALUE`` reads its
        text (Flitter's rule: "-3" is a number, "" the empty string, "a;b"
        two strings), and so is a sequence that holds text, its parts
        joined with ";". Raises FlitterError for a name that is not one,
        ValueError for a Symbol holding ";" or a NUL."""
        parts = value if isinstance(value, (list, tuple)) else [value]
        if any(isinstance(v, Symbol) and ";" in v for v in parts):
            raise ValueError(f"a defined symbol cannot hold ';': {value!r}")
        arr = None if value is None else _define_numbers(value)
        k = _c(name)
        with self._lock:
            if value is None:
                rc = lib.fl_define_numbers(self._rt, k, ffi.NULL, 0)
            elif arr is not None:
                rc = lib.fl_define_numbers(self._rt, k, ffi.cast("const double *", arr.ctypes.data), arr.size)
            else:
                rc = lib.fl_define(self._rt, k, _c(define_text(value)))
            if rc != 0:
                raise self._error()

    def load(self, path: str) -> None:
        """Load (or reload, keeping the state) the script at ``path``.
        Raises FlitterError with path, line and col for a malformed script
        (the previous program stays loaded)."""
        with self._lock:
            if lib.fl_load(self._rt, _c(os.fspath(path))) != 0:
                raise self._error()

    def load_text(self, text: str, name: str = "<text>") -> None:
        """Load program text from memory (``name`` is used in messages)."""
        data = text.encode("utf-8")
        with self._lock:
            if lib.fl_load_text(self._rt, _c(name), data, len(data)) != 0:
                raise self._error()

    def step(self, n: int = 1) -> int:
        """Evaluate and simulate ``n`` frames (each advances ``time`` by
        1/fps s in lockstep); returns the frames run. The GIL is released
        inside each frame. Run-time script errors do not raise: they are
        logged (``messages``, logger "flitter_c")."""
        done = 0
        with self._lock:
            for _ in range(int(n)):
                rc = lib.fl_step(self._rt)
                if rc < 0:
                    raise self._error() if ffi.string(lib.fl_error(self._rt)) else FlitterError("no program loaded")
                done += 1
        return done

    @property
    def frames(self) -> int:
        """Frames evaluated so far."""
        with self._lock:
            return int(lib.fl_frame_count(self._rt))

    @property
    def frame(self) -> int:
        """The number of the last evaluated frame, as the state dump's
        ``frame N`` line (-1 before the first)."""
        with self._lock:
            return int(lib.fl_frame_count(self._rt)) - 1

    @property
    def time(self) -> float:
        """The ``time`` of the last evaluated frame, seconds (0 before the
        first)."""
        with self._lock:
            return float(lib.fl_frame_time(self._rt))

    def _particles(self, system: Any):
        out: Tuple[list, list, list] = ([], [], [])
        h = ffi.new_handle(out)
        with self._lock:
            if lib.fl_particles(self._rt, _c(_system_text(system)), lib._py_particle, h) < 0:
                raise self._error()
        return out

    def positions(self, system: Any) -> Tuple[List[Any], np.ndarray]:
        """The particles of the !physics system with ``state=`` prefix
        ``system`` ("dish" or ":dish" for the symbol ``:dish``; a tuple for
        a longer prefix): their ids (int/float for numbers, str for symbols
        and strings, a tuple for longer ids) and a float64 array of shape
        (n, D) of their positions, in the order of the state dump. Empty
        (shape (0, 0)) before the system's first frame."""
        ids, pos, _ = self._particles(system)
        return [parse_id(i) for i in ids], _matrix(pos)

    def velocities(self, system: Any) -> Tuple[List[Any], np.ndarray]:
        """As ``positions``, with the particles' velocities (units per
        second of the system's clock), shape (n, D)."""
        ids, _, vel = self._particles(system)
        return [parse_id(i) for i in ids], _matrix(vel)

    def dump_state(self) -> str:
        """The state dump of the last frame, as ``flitter run --dump-state``
        prints it."""
        chunks: List[bytes] = []
        with self._lock:
            lib.fl_dump_state(self._rt, lib._py_write, ffi.new_handle(chunks))
        return b"".join(chunks).decode("utf-8", "surrogateescape")

    def tree_text(self) -> str:
        """The last frame's node tree as ``--dump-tree`` prints it ("" before
        the first frame)."""
        chunks: List[bytes] = []
        with self._lock:
            lib.fl_dump_tree(self._rt, lib._py_write, ffi.new_handle(chunks))
        return b"".join(chunks).decode("utf-8", "surrogateescape")

    def tree(self) -> Optional[Node]:
        """The last frame's node tree (the ``!root`` Node), or None before
        the first frame."""
        text = self.tree_text()
        if not text:
            return None
        root: Optional[Node] = None
        stack: List[Tuple[int, Node]] = []
        for line in text.splitlines():
            depth = len(line) - len(line.lstrip(" "))
            words = _tree_tokens(line)
            if not words or not words[0].startswith("!"):
                continue
            attrs = {}
            for w in words[1:]:
                name, _, value = w.partition("=")
                attrs[name] = parse_value(value)
            node = Node(words[0][1:], attrs, [])
            while stack and stack[-1][0] >= depth:
                stack.pop()
            if stack:
                stack[-1][1].children.append(node)
            else:
                root = node
            stack.append((depth, node))
        return root

    def save_state(self, path: str) -> None:
        """Save the state and the clock to ``path`` atomically (the format
        of ``flitter run --state``)."""
        with self._lock:
            if lib.fl_save_state(self._rt, _c(os.fspath(path))) != 0:
                raise self._error()

    def load_state(self, path: str) -> None:
        """Restore the state and the clock from ``path``; FlitterError (and
        nothing changed) for a missing or malformed file."""
        with self._lock:
            if lib.fl_restore_state(self._rt, _c(os.fspath(path))) != 0:
                raise self._error()

    def picture(self, window: Optional[int] = None, size: Tuple[int, int] = (512, 512)) -> np.ndarray:
        """The last frame's picture as a uint8 array of shape (height,
        width, 4), RGBA, premultiplied alpha: window ``window`` (its own
        size), or with None the first window if the frame has one, else the
        physics view drawn at ``size`` (width, height) pixels."""
        with self._lock:
            nwin = lib.fl_windows(self._rt, ffi.NULL, 0)
            if window is not None or nwin:
                index = 0 if window is None else int(window)
                infos = ffi.new("fl_window_info[]", max(nwin, 1))
                lib.fl_windows(self._rt, infos, nwin)
                if index >= nwin:
                    raise FlitterError(f"no window {index} (the frame has {nwin})")
                w, h = infos[index].width, infos[index].height
                px = np.zeros((h, w), dtype=np.uint32)
                rc = lib.fl_draw_window(self._rt, index, ffi.cast("uint32_t *", px.ctypes.data), w, h, w * 4)
            else:
                w, h = size
                px = np.zeros((h, w), dtype=np.uint32)
                rc = lib.fl_draw_view(self._rt, ffi.cast("uint32_t *", px.ctypes.data), w, h, w * 4, ffi.NULL)
            if rc != 0:
                raise self._error()
        rgba = np.empty((h, w, 4), dtype=np.uint8)
        rgba[..., 0] = (px >> 16) & 0xFF
        rgba[..., 1] = (px >> 8) & 0xFF
        rgba[..., 2] = px & 0xFF
        rgba[..., 3] = (px >> 24) & 0xFF
        return rgba

    def render(self, path: str) -> None:
        """Write the last frame's picture to ``path``: with a !window in the
        frame, a .png of the first window (via ``picture`` and matplotlib);
        else the physics view (.png or .svg, as ``flitter run --view``)."""
        path = os.fspath(path)
        with self._lock:
            nwin = lib.fl_windows(self._rt, ffi.NULL, 0)
            if not nwin:
                if lib.fl_view(self._rt, _c(path), ffi.NULL) != 0:
                    raise self._error()
                return
        import matplotlib.image
        rgba = self.picture(0)
        tmp = path + ".tmp.png"
        matplotlib.image.imsave(tmp, rgba, format="png")
        os.replace(tmp, path)


def _system_text(system: Any) -> str:
    if isinstance(system, str) and not isinstance(system, Symbol) and not system.startswith(":") \
            and ";" not in system:
        return ":" + system
    return key_text(system)


def _matrix(rows: List[List[float]]) -> np.ndarray:
    if not rows:
        return np.zeros((0, 0), dtype=np.float64)
    return np.array(rows, dtype=np.float64)


def load(path: str, defines: Optional[Mapping[str, Any]] = None, simplify: bool = True,
         fps: float = 60.0, physics: str = "documented", threads: int = 0) -> Simulation:
    """A new Simulation running the script at ``path``: ``defines`` bound
    first (as ``flitter run -D NAME=VALUE``; numbers exact, lists as
    vectors, Symbol as a symbol), the simplifier on unless ``simplify`` is
    False, ``fps`` frames per second of frame clock, ``physics``
    "documented" or "upstream", ``threads`` physics threads (0: all
    cores). Raises FlitterError with path/line/col for a malformed script
    and OSError-like FlitterError for a missing one."""
    sim = Simulation(fps=fps, simplify=simplify, physics=physics, threads=threads)
    for name, value in (defines or {}).items():
        sim.define(name, value)
    sim.load(path)
    return sim
