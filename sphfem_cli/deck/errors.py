"""One-line deck errors: ``file:line:col: path.in.deck: what is wrong (what was expected)``."""
from __future__ import annotations

import difflib
import json
import re
from collections.abc import Hashable, Iterable, Sequence

__all__ = ["ROOT", "DeckError", "DeckErrors", "did_you_mean", "format_path", "parse_path"]

ROOT = "<root>"
"""How the empty path (the whole deck) is written in messages."""

_SEGMENT = re.compile(r'\[(-?\d+)\]|\[("(?:[^"\\]|\\.)*")\]|([^.\[\]]+)')
_QUOTED = re.compile(r'[.\[\]"]|^\s|\s$|^$|[^\S ]')  # also any white space but the plain space


def format_path(path: Iterable[Hashable]) -> str:
    """Dotted path with list indices in brackets: ``("bcs", 0, "part")`` -> ``bcs[0].part``.

    A key that is empty, starts or ends with white space, or holds ``.``, ``[``, ``]``, ``"`` or
    white space other than a space is written as a JSON string in brackets: ``("parts", "a.b")`` ->
    ``parts["a.b"]``. :class:`DeckError` writes what is still not printable as ``\\uXXXX``.
    """
    text = ""
    for key in path:
        if isinstance(key, int):
            text += f"[{key}]"
        elif _QUOTED.search(str(key)):
            text += f"[{json.dumps(str(key), ensure_ascii=False)}]"
        else:
            text += f".{key}" if text else str(key)
    return text


def parse_path(text: str) -> tuple[str | int, ...]:
    """Inverse of :func:`format_path`; ``a.0.b`` keeps ``"0"`` as a string (see validate.py)."""
    text = text.strip()
    if text in ("", ROOT):
        return ()
    return tuple(int(m[1]) if m[1] is not None else json.loads(m[2]) if m[2] is not None else m[3]
                 for m in _SEGMENT.finditer(text))


def _printable(text: str) -> str:
    """``text`` with every non-printable character (controls, separators, escapes) as ``\\uXXXX``."""
    return "".join(ch if ch.isprintable() else f"\\u{ord(ch):04x}" if ord(ch) < 0x10000 else f"\\U{ord(ch):08x}"
                   for ch in text)


def _one_line(text: str) -> str:
    return _printable(" ".join(str(text).split()))


class DeckError(Exception):
    """A problem in a deck, located at ``file:line:col`` (1-based) and a dotted ``path``.

    ``str(error)`` is always a single line:
    ``deck.yaml:12:5: parts.plate.material: unknown material 'stel' (known: steel, water)``.
    """

    def __init__(self, message: str, *, file: str = "<deck>", line: int = 1, col: int = 1,
                 path: str = "") -> None:
        self.message = _one_line(message)
        self.file = str(file)
        self.line = int(line)
        self.col = int(col)
        self.path = _printable(str(path))
        super().__init__(str(self))

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}: {self.path or ROOT}: {self.message}"

    def __repr__(self) -> str:
        return f"DeckError({str(self)!r})"


class DeckErrors(DeckError):
    """Several deck errors, sorted by position; behaves as (and prints as) the first one."""

    def __init__(self, errors: Sequence[DeckError]) -> None:
        if not errors:
            raise ValueError("DeckErrors needs at least one error")
        self.errors = list(errors)
        first = self.errors[0]
        super().__init__(first.message, file=first.file, line=first.line, col=first.col,
                         path=first.path)

    def __repr__(self) -> str:
        return f"DeckErrors({[str(e) for e in self.errors]!r})"


def did_you_mean(word: object, candidates: Iterable[object], cutoff: float = 0.6) -> str | None:
    """The candidate closest to ``word`` (difflib, case-insensitive), or None if none is close."""
    if not isinstance(word, str):
        return None
    names = {str(c).lower(): str(c) for c in candidates}
    close = difflib.get_close_matches(word.lower(), list(names), n=1, cutoff=cutoff)
    return names[close[0]] if close else None
