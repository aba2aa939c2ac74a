"""Value text (FORMATS.md §1) to and from Python values.

Value text is what the state dump prints: parts joined by ``;``, each a
number (shortest round-trip decimal, ``nan``, ``inf``), a symbol
``:name`` or a double-quoted string with ``\\"`` ``\\\\`` ``\\n`` ``\\r``
``\\t`` ``\\xHH`` escapes; ``null`` is the empty vector.
"""
from __future__ import annotations

from typing import Any, List, Union

import numpy as np


class Symbol(str):
    """A Flitter symbol (``:name``): a ``str`` holding the name without the
    colon. Written back to the state as a symbol, where a plain ``str`` is
    written as a string."""

    __slots__ = ()

    def __repr__(self) -> str:
        return f"Symbol({str.__repr__(self)})"


Part = Union[float, str]

_ESCAPES = {'"': '"', "\\": "\\", "n": "\n", "r": "\r", "t": "\t"}


def split_parts(text: str) -> List[Part]:
    """Split value text into its parts: float, Symbol or str."""
    parts: List[Part] = []
    if text == "null" or text == "":
        return parts
    i, n = 0, len(text)
    while i <= n:
        if i < n and text[i] == '"':
            i += 1
            out = []
            while i < n and text[i] != '"':
                c = text[i]
                if c == "\\" and i + 1 < n:
                    e = text[i + 1]
                    if e == "x" and i + 3 < n + 1:
                        out.append(chr(int(text[i + 2:i + 4], 16)))
                        i += 4
                        continue
                    out.append(_ESCAPES.get(e, e))
                    i += 2
                    continue
                out.append(c)
                i += 1
            parts.append("".join(out))
            i += 1  # closing quote
            if i < n and text[i] == ";":
                i += 1
            elif i >= n:
                break
            continue
        j = text.find(";", i)
        if j < 0:
            j = n
        tok = text[i:j]
        if tok.startswith(":"):
            parts.append(Symbol(tok[1:]))
        else:
            parts.append(float(tok))
        i = j + 1
        if j == n:
            break
    return parts


def parse_value(text: str) -> Any:
    """Value text to a Python value: None for null; a float for one number;
    a float64 ``numpy.ndarray`` of shape (n,) for n > 1 numbers; a Symbol or
    str for one symbol or string; else a tuple of the parts."""
    parts = split_parts(text)
    if not parts:
        return None
    if len(parts) == 1:
        return parts[0]
    if all(isinstance(p, float) for p in parts):
        return np.array(parts, dtype=np.float64)
    return tuple(parts)


def parse_id(text: str) -> Any:
    """A particle id's value text to a Python value: an int for an integral
    number, else a float; a str for a symbol or string; a tuple for more
    than one part."""
    parts = split_parts(text)

    def one(p: Part) -> Any:
        if isinstance(p, float) and p.is_integer():
            return int(p)
        return p if not isinstance(p, Symbol) else str(p)

    if len(parts) == 1:
        return one(parts[0])
    return tuple(one(p) for p in parts)


def key_text(key: Any) -> str:
    """A state key as the key text the library parses: a str is taken as
    value text (``":dish;0"``); a tuple's parts are joined with ``;``
    (Symbol → ``:name``, str as is, numbers in shortest round-trip form)."""
    if isinstance(key, Symbol):
        return ":" + key
    if isinstance(key, str):
        return key
    if isinstance(key, tuple):
        return ";".join(key_text(k) if isinstance(k, str) else number_text(k) for k in key)
    return number_text(key)


def number_text(x: Any) -> str:
    """A number as value text, exact (Python's repr is the shortest decimal
    that reads back to the same double)."""
    x = float(x)
    if x.is_integer() and abs(x) < 1e15:
        return str(int(x)) if x or str(x)[0] != "-" else "-0.0"
    if x != x:
        return "nan"
    if x in (float("inf"), float("-inf")):
        return "inf" if x > 0 else "-inf"
    return repr(x)


def define_text(value: Any) -> str:
    """A define's value (``-D NAME=VALUE``) as value text: numbers exact,
    Symbol as ``:name``, sequences joined by ``;``."""
    if isinstance(value, Symbol):
        return ":" + value
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple, np.ndarray)):
        return ";".join(define_text(v) for v in value)
    return number_text(value)
