"""YAML deck loading with source positions.

The text is composed into a PyYAML node tree (``yaml.compose``) and the Python objects are built
here from the nodes, so that every key path can be mapped back to its line and column.

Scalars follow the YAML 1.2 core schema, not PyYAML's YAML 1.1 rules. Only *plain* (unquoted)
scalars are resolved; quoted and block scalars are always strings:

=========  ==========================================================================
null       ``null``, ``Null``, ``NULL``, ``~``, empty
bool       ``true``, ``True``, ``TRUE``, ``false``, ``False``, ``FALSE``
int        ``[-+]?[0-9]+``, ``0o[0-7]+``, ``0x[0-9a-fA-F]+``
float      ``[-+]?(\\.[0-9]+|[0-9]+(\\.[0-9]*)?)([eE][-+]?[0-9]+)?`` (so ``1e-3``, ``.5``,
           ``-2E3``, ``1.`` are floats), ``[-+]?.inf`` (any of the three casings), ``.nan``
string     everything else, including the YAML 1.1 forms ``yes``, ``no``, ``on``, ``off``,
           ``1_000``, ``0b101``, ``1:30``, ``-0x1F`` and ``-.nan``
=========  ==========================================================================

Explicit tags ``!!str``, ``!!int``, ``!!float``, ``!!bool``, ``!!null``, ``!!seq``, ``!!map``
are honoured; any other tag is an error. Anchors, aliases and merge keys (``<<: *base`` or
``<<: [*a, *b]``) work: keys written in the mapping win over merged ones, and earlier merge
sources win over later ones. Duplicate keys, non-string keys, recursive aliases and streams with
more than one document are errors.

Positions are 1-based ``(line, col)``. :class:`Positions` maps each key path (a tuple of mapping
keys and list indices, e.g. ``("parts", "plate", "material")``) to the position of the key (for a
mapping entry) or of the item (for a sequence item); ``Positions.values`` maps the same paths to
the position where the value starts. The empty path ``()`` is the document's root node.

Bounds (each a one-line :class:`DeckError` naming the limit and the environment variable that
raises it, read when a deck is loaded; see :data:`LIMITS`):

==========================  ==========  ======================================================
``SPHFEM_MAX_DECK_BYTES``   8388608     size of the deck file (8 MiB; the pure-Python scanner
                                        reads about 3 MB/s of comments)
``SPHFEM_MAX_DECK_NODES``   100000      YAML values (scalars, lists, mappings) in the deck with
                                        every alias and merge key expanded: an alias bomb
                                        ("billion laughs") stops here, after at most this many
``SPHFEM_MAX_DECK_DEPTH``   100         nesting of lists and mappings (PyYAML's composer
                                        recurses once per level)
==========================  ==========  ======================================================

A deck must be a regular file (not a FIFO, a device or a directory).
"""
from __future__ import annotations

import math
import os
import re
import stat
from collections.abc import Hashable
from os import PathLike
from typing import Any

import yaml
from yaml.composer import Composer
from yaml.events import AliasEvent, MappingStartEvent, SequenceStartEvent
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode
from yaml.parser import Parser
from yaml.reader import Reader
from yaml.resolver import BaseResolver
from yaml.scanner import Scanner

from .errors import DeckError, format_path

__all__ = ["LIMITS", "Positions", "limit", "load", "loads", "resolve_plain_scalar"]

Path_ = tuple[Hashable, ...]

_PLAIN = "tag:sphfem,2024:plain"
_TAG = "tag:yaml.org,2002:"
_T_STR, _T_INT, _T_FLOAT, _T_BOOL, _T_NULL, _T_SEQ, _T_MAP, _T_MERGE = (
    _TAG + t for t in ("str", "int", "float", "bool", "null", "seq", "map", "merge"))

LIMITS = {"SPHFEM_MAX_DECK_BYTES": 8 * 2**20, "SPHFEM_MAX_DECK_NODES": 100_000, "SPHFEM_MAX_DECK_DEPTH": 100}
"""Default bounds on a deck, by the environment variable that overrides each (module docstring)."""


def limit(name: str, file: str = "<deck>") -> int:
    """The bound ``name`` of :data:`LIMITS`: the environment's value if set, else the default."""
    text = os.environ.get(name, "").strip()
    if not text:
        return LIMITS[name]
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise DeckError(f"the environment variable {name}={text!r} must be a positive integer",
                        file=file, line=1, col=1, path="")
    return value


def _over(what: str, name: str, value: int, unit: str = "") -> str:
    return f"{what} {value}{unit} (the limit {name}; set the environment variable {name} to raise it)"


_NULLS = {"", "~", "null", "Null", "NULL"}
_BOOLS = {"true": True, "True": True, "TRUE": True, "false": False, "False": False, "FALSE": False}
_INT_DEC = re.compile(r"[-+]?[0-9]+\Z")
_INT_OCT = re.compile(r"0o[0-7]+\Z")
_INT_HEX = re.compile(r"0x[0-9a-fA-F]+\Z")
_FLOAT = re.compile(r"[-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?\Z")
_INF = re.compile(r"[-+]?\.(inf|Inf|INF)\Z")
_NAN = re.compile(r"\.(nan|NaN|NAN)\Z")


def resolve_plain_scalar(text: str) -> Any:
    """Value of a plain scalar under the YAML 1.2 core schema (see the module docstring)."""
    if text in _NULLS:
        return None
    if text in _BOOLS:
        return _BOOLS[text]
    if _INT_DEC.match(text):
        return int(text)
    if _INT_OCT.match(text):
        return int(text[2:], 8)
    if _INT_HEX.match(text):
        return int(text[2:], 16)
    if _FLOAT.match(text):
        return float(text)
    if _INF.match(text):
        return -math.inf if text[0] == "-" else math.inf
    if _NAN.match(text):
        return math.nan
    return text


class Positions(dict):
    """Key path -> 1-based ``(line, col)`` of the key or sequence item; ``values``: of the value."""

    def __init__(self) -> None:
        super().__init__()
        self.values: dict[Path_, tuple[int, int]] = {}

    def _indexed(self, path: Path_) -> Path_:
        out: Path_ = ()
        for key in path:
            if isinstance(key, str) and key.isdigit() and out + (int(key),) in self:
                key = int(key)
            out += (key,)
        return out

    def nearest(self, path: Path_) -> Path_:
        """Longest known prefix of ``path`` (itself included); ``"0"`` may stand for index 0."""
        path = self._indexed(path)
        while path and path not in self:
            path = path[:-1]
        return path

    def position_of(self, path: Path_, *, value: bool = False) -> tuple[int, int]:
        """Position of ``path``, or of its nearest known ancestor; ``value`` picks the value's."""
        known = self.nearest(path)
        table = self.values if value and known == self._indexed(path) else self
        return table.get(known, self.get(known, (1, 1)))


class _Resolver(BaseResolver):
    """Marks plain scalars so that they are resolved by :func:`resolve_plain_scalar`."""

    def resolve(self, kind: type, value: Any, implicit: tuple[bool, bool]) -> str:
        if kind is ScalarNode:
            return _PLAIN if implicit[0] else _T_STR
        return _T_SEQ if kind is SequenceNode else _T_MAP


class _Composer(Reader, Scanner, Parser, Composer, _Resolver):
    """PyYAML's pure-Python pipeline up to the node graph, with :class:`_Resolver`.

    Counts the nodes it composes and the nesting depth, and stops at ``max_nodes`` or
    ``max_depth`` with a DeckError at the node that crossed the bound.
    """

    def __init__(self, stream: str, file: str = "<string>", max_nodes: int | None = None,
                 max_depth: int | None = None) -> None:
        Reader.__init__(self, stream)
        Scanner.__init__(self)
        Parser.__init__(self)
        Composer.__init__(self)
        _Resolver.__init__(self)
        self.file = file
        self.max_nodes = max_nodes if max_nodes is not None else limit("SPHFEM_MAX_DECK_NODES", file)
        self.max_depth = max_depth if max_depth is not None else limit("SPHFEM_MAX_DECK_DEPTH", file)
        self.n_nodes = 0
        self.depth = 0

    def _stop(self, event: Any, message: str) -> DeckError:
        line, col = _mark_pos(event.start_mark)
        return DeckError(message, file=self.file, line=line, col=col, path="yaml")

    def compose_node(self, parent: Node | None, index: Any) -> Node:
        event = self.peek_event()
        if isinstance(event, AliasEvent):
            return super().compose_node(parent, index)
        self.n_nodes += 1
        if self.n_nodes > self.max_nodes:
            raise self._stop(event, _over("the deck holds more values than", "SPHFEM_MAX_DECK_NODES",
                                          self.max_nodes))
        if not isinstance(event, (SequenceStartEvent, MappingStartEvent)):
            return super().compose_node(parent, index)
        self.depth += 1
        if self.depth > self.max_depth:
            raise self._stop(event, _over("lists and mappings nested deeper than",
                                          "SPHFEM_MAX_DECK_DEPTH", self.max_depth))
        try:
            return super().compose_node(parent, index)
        finally:
            self.depth -= 1


def _mark_pos(mark: Any) -> tuple[int, int]:
    """1-based (line, col) of a PyYAML mark, lines counted at "\\n" only, as editors count them (PyYAML also
    breaks lines at NEL U+0085 and at U+2028 / U+2029; the composer reads the whole text, so the mark's buffer
    holds it)."""
    if mark.buffer is not None:
        return _line_col(mark.buffer, mark.index)
    return mark.line + 1, mark.column + 1


def _pos(node: Node) -> tuple[int, int]:
    return _mark_pos(node.start_mark)


def _kind(value: Any) -> str:
    if value is None:
        return "null"
    return {dict: "mapping", list: "list"}.get(type(value), type(value).__name__)


class _Builder:
    """Builds Python objects from a node tree, recording positions and rejecting bad structure."""

    def __init__(self, file: str, max_nodes: int, max_depth: int) -> None:
        self.file = file
        self.positions = Positions()
        self.active: set[int] = set()
        self.max_nodes, self.max_depth = max_nodes, max_depth
        self.n_nodes = 0

    def error(self, node: Node, path: Path_, message: str) -> DeckError:
        line, col = _pos(node)
        return DeckError(message, file=self.file, line=line, col=col, path=format_path(path))

    def count(self, node: Node, path: Path_, n: int = 1) -> None:
        """Count ``n`` values built (aliases and merges expanded); stop past ``max_nodes``."""
        self.n_nodes += n
        if self.n_nodes > self.max_nodes:
            raise self.error(node, path, _over("with its aliases and merge keys expanded the deck "
                                               "holds more values than", "SPHFEM_MAX_DECK_NODES",
                                               self.max_nodes))

    def build(self, node: Node, path: Path_) -> Any:
        if id(node) in self.active:
            raise self.error(node, path, "recursive alias (a node that contains itself)")
        self.count(node, path)
        if len(path) >= self.max_depth and not isinstance(node, ScalarNode):  # aliases nest too
            raise self.error(node, path[:1], _over("with its aliases expanded, lists and mappings nest deeper "
                                                   "than", "SPHFEM_MAX_DECK_DEPTH", self.max_depth))
        self.positions.values[path] = _pos(node)
        self.active.add(id(node))
        try:
            if isinstance(node, ScalarNode):
                return self.scalar(node, path)
            if node.tag not in (_T_SEQ, _T_MAP):
                raise self.error(node, path, f"unsupported tag '{node.tag}'")
            if isinstance(node, SequenceNode):
                return self.sequence(node, path)
            return self.mapping(node, path)
        finally:
            self.active.discard(id(node))

    def scalar(self, node: ScalarNode, path: Path_) -> Any:
        text, tag = node.value, node.tag
        if tag == _PLAIN:
            return resolve_plain_scalar(text)
        if tag == _T_STR:
            return text
        value = resolve_plain_scalar(text.strip())
        expected = {_T_INT: int, _T_FLOAT: float, _T_BOOL: bool, _T_NULL: type(None)}.get(tag)
        if expected is None:
            raise self.error(node, path, f"unsupported tag '{tag}'")
        if expected is float and type(value) is int:
            return float(value)
        if type(value) is not expected:
            raise self.error(node, path, f"'{text}' is not a valid {tag.rsplit(':', 1)[-1]}")
        return value

    def sequence(self, node: SequenceNode, path: Path_) -> list[Any]:
        items = []
        for index, item in enumerate(node.value):
            self.positions[path + (index,)] = _pos(item)
            items.append(self.build(item, path + (index,)))
        return items

    def key(self, node: Node, path: Path_) -> str:
        if not isinstance(node, ScalarNode):
            raise self.error(node, path, "mapping keys must be plain names, not a list or mapping")
        key = self.scalar(node, path)
        if not isinstance(key, str):
            raise self.error(node, path, f"mapping key {node.value!r} is not a name (it reads "
                                         f"as {_kind(key)}); quote it if it is meant as one")
        return key

    def merge_sources(self, node: Node, path: Path_) -> list[MappingNode]:
        if isinstance(node, MappingNode):
            return [node]
        if isinstance(node, SequenceNode) and all(isinstance(n, MappingNode) for n in node.value):
            return list(node.value)
        raise self.error(node, path, "a merge key '<<' takes a mapping or a list of mappings")

    def pairs(self, node: MappingNode, path: Path_) -> list[tuple[Node, Node, str]]:
        """``(key node, value node, key)`` in precedence order: own keys, then merged ones."""
        own: list[tuple[Node, Node, str]] = []
        merged: list[tuple[Node, Node, str]] = []
        first: dict[str, Node] = {}
        for key_node, value_node in node.value:
            if key_node.tag == _PLAIN and key_node.value == "<<" or key_node.tag == _T_MERGE:
                for source in self.merge_sources(value_node, path):
                    if id(source) in self.active:
                        raise self.error(source, path, "recursive merge (a mapping merges itself)")
                    self.active.add(id(source))
                    try:
                        pairs = self.pairs(source, path)
                        self.count(source, path, len(pairs))
                        merged.extend(pairs)
                    finally:
                        self.active.discard(id(source))
                continue
            key = self.key(key_node, path)
            if key in first:
                raise self.error(key_node, path + (key,),
                                 f"duplicate key '{key}' (first at line {_pos(first[key])[0]})")
            first[key] = key_node
            own.append((key_node, value_node, key))
        return own + merged

    def mapping(self, node: MappingNode, path: Path_) -> dict[str, Any]:
        result: dict[str, Any] = {}
        for key_node, value_node, key in self.pairs(node, path):
            if key in result:
                continue
            self.positions[path + (key,)] = _pos(key_node)
            result[key] = self.build(value_node, path + (key,))
        return result


def _line_col(text: str, index: int) -> tuple[int, int]:
    line = text.count("\n", 0, index) + 1
    return line, index - (text.rfind("\n", 0, index) + 1) + 1


def _syntax_error(exc: yaml.YAMLError, text: str, file: str) -> DeckError:
    if isinstance(exc, yaml.MarkedYAMLError):
        mark = exc.problem_mark or exc.context_mark
        message = exc.problem or exc.context or "invalid YAML"
        context = exc.context_mark
        if exc.context and exc.problem and context and mark and context.line != mark.line:
            message = f"{exc.problem} ({exc.context} at line {_mark_pos(context)[0]})"
        if (exc.context or "").startswith("expected a single document"):
            message = "more than one YAML document ('---'); a deck is a single document"
        line, col = _mark_pos(mark) if mark else (1, 1)
    elif isinstance(exc, yaml.reader.ReaderError):
        line, col = _line_col(text, exc.position)
        message = f"unacceptable character #x{exc.character:04x}: {exc.reason}"
    else:
        line, col, message = 1, 1, str(exc)
    return DeckError(" ".join(message.split()), file=file, line=line, col=col, path="yaml")


def loads(text: str, file: str = "<string>") -> tuple[Any, Positions]:
    """Parse one YAML document from ``text``; return ``(data, positions)``.

    Raises :class:`DeckError` for syntax errors, an empty stream, several documents, duplicate or
    non-string keys, unsupported tags, recursive aliases, and decks past the node or depth bounds.
    """
    max_nodes, max_depth = limit("SPHFEM_MAX_DECK_NODES", file), limit("SPHFEM_MAX_DECK_DEPTH", file)
    try:
        composer = _Composer(text, file, max_nodes, max_depth)  # the reader checks the characters here
        root = composer.get_single_node()
    except yaml.YAMLError as exc:
        raise _syntax_error(exc, text, file) from None
    except RecursionError:  # SPHFEM_MAX_DECK_DEPTH set beyond what Python's stack allows
        raise _too_deep(file, max_depth) from None
    if root is None:
        raise DeckError("the file is empty (no YAML document)", file=file, line=1, col=1, path="")
    builder = _Builder(file, max_nodes, max_depth)
    builder.positions[()] = _pos(root)
    try:
        data = builder.build(root, ())
    except RecursionError:
        raise _too_deep(file, max_depth) from None
    return data, builder.positions


def _too_deep(file: str, depth: int) -> DeckError:
    return DeckError(f"lists and mappings nested deeper than Python's stack allows (SPHFEM_MAX_DECK_DEPTH "
                     f"is {depth}; lower it)", file=file, line=1, col=1, path="yaml")


def load(path: str | PathLike[str]) -> tuple[Any, Positions]:
    """Read and parse the YAML file at ``path`` (UTF-8, a regular file within
    ``SPHFEM_MAX_DECK_BYTES``); see :func:`loads`."""
    file = str(path)
    max_bytes = limit("SPHFEM_MAX_DECK_BYTES", file)
    try:
        raw = read_regular_file(path, max_bytes, "a deck")
    except FileNotFoundError:
        raise DeckError("no such file", file=file, line=1, col=1) from None
    except (OSError, ValueError) as exc:
        raise DeckError(_reason(exc), file=file, line=1, col=1) from None
    if len(raw) > max_bytes:
        raise DeckError(_over("the deck file is larger than", "SPHFEM_MAX_DECK_BYTES", max_bytes, " bytes"),
                        file=file, line=1, col=1)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        before = raw[:exc.start].decode("utf-8", "replace")
        line, col = _line_col(before, len(before))
        raise DeckError(f"not UTF-8 text (byte 0x{raw[exc.start]:02x})", file=file, line=line,
                        col=col, path="yaml") from None
    return loads(text, file)


def _reason(exc: Exception) -> str:
    if isinstance(exc, OSError):
        return f"cannot read: {exc.strerror or exc}"
    return str(exc)


def read_regular_file(path: str | PathLike[str], max_bytes: int, what: str) -> bytes:
    """The bytes of ``path``, at most ``max_bytes + 1`` of them (so a caller sees it is too large).

    ``ValueError`` unless ``path`` is a regular file: a FIFO would block the read forever, a
    device (``/dev/zero``) never ends, a directory has no bytes. The file is opened without
    blocking and checked with ``fstat`` on the open descriptor (no race between check and read).
    """
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            kind = ("a directory" if stat.S_ISDIR(mode) else "a FIFO (named pipe)" if stat.S_ISFIFO(mode)
                    else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else "a socket"
                    if stat.S_ISSOCK(mode) else "not a regular file")
            raise ValueError(f"is {kind}, not a regular file; {what} must be a regular file")
        chunks, size = [], 0
        while size <= max_bytes:
            chunk = os.read(fd, min(max_bytes + 1 - size, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        return b"".join(chunks)
    finally:
        os.close(fd)
