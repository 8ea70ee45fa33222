"""The mutable state of a `Simulation` as named data, and its restoration into a freshly built one.

A restart rebuilds the `Simulation` from the deck exactly as a fresh run does, then overwrites its
state by name. :func:`capture` walks the object graph from the simulation deterministically
(an object's attributes in sorted order, a dict's items and a list's elements in their order) and
describes every value as a JSON tree whose leaves are

    numbers, strings, booleans, None   as themselves
    numpy arrays                       {"t": "array", "a": index into the array list, "mem": buffer group}
    numpy scalars                      {"t": "np", "dtype": ..., "v": ...}
    slices, sets                       {"t": "slice" | "set" | "frozenset", ...}
    configuration                      {"t": "skip", "type": ...}: deck objects (pydantic models), the
                                       settings resolved from them (model.options), numba dispatchers and paths; they come from the deck and the code, never
                                       from a checkpoint, and are only checked to be of the same type

and whose inner nodes are objects with a ``__dict__`` ({"t": "obj", "cls": module.qualname, "attrs": ...}), lists,
tuples and dicts. An object, list, dict or array reached a second time is {"t": "ref", "to": id},
so shared references stay shared. "mem" numbers the distinct memory buffers (the base of a view),
so arrays that shared memory when the checkpoint was written are known to.

:func:`restore` walks the saved tree and the fresh graph together. An array is copied into the fresh
array at the same place when that has the same shape and dtype and its buffer corresponds to the
same saved buffer as every array copied so far (so the views a fresh build makes stay views of the
same buffers); otherwise the loaded array is bound in its place (an array the run had replaced, e.g.
resized scratch space). Objects are never created: the fresh graph must hold an object of the same
class wherever the tree has one, with the same attributes (a lazily set attribute that the fresh
object lacks is created when it is plain data). Lists and dicts are restored in place, so other
references to them see the restored content. Any mismatch is a :class:`SnapshotMismatch`.

Contract for state-holding classes: their instances keep plain attributes (numpy arrays of a
non-object dtype, numbers, strings, lists, tuples, dicts with str or int keys, sets of numbers,
slices, and references to other sphfem objects or to deck objects); anything else makes
:func:`capture` raise TypeError, naming the attribute.
"""
from __future__ import annotations

import types
from pathlib import PurePath
from typing import Any

import numpy as np

__all__ = ["capture", "restore", "SnapshotMismatch"]

_MISSING = object()
_SCALARS = (bool, int, float, str, type(None))
_CODE = (type, types.ModuleType, types.FunctionType, types.MethodType, types.BuiltinFunctionType)


class SnapshotMismatch(Exception):
    """The saved tree does not fit the freshly built graph; the message names the first place."""


def _skipped_types() -> tuple[type, ...]:
    import pydantic
    from numba.core.dispatcher import Dispatcher

    from ..model.options import Options

    return (pydantic.BaseModel, Options, Dispatcher, PurePath)


def _cls(value: Any) -> str:
    t = type(value)
    return f"{t.__module__}.{t.__qualname__}"


def _root(a: np.ndarray) -> np.ndarray:
    """The array owning the memory of `a` (the end of its chain of view bases)."""
    while isinstance(a.base, np.ndarray):
        a = a.base
    return a


class _Capture:
    def __init__(self):
        self.arrays: list[np.ndarray] = []
        self.memo: dict[int, int] = {}  # id(value) -> node id
        self.roots: dict[int, int] = {}  # id(buffer root) -> "mem" group
        self.alive: list[Any] = []  # keeps every memoised value alive so that ids stay unique
        self.skipped = _skipped_types()

    def _id(self, value: Any) -> int:
        n = len(self.memo)
        self.memo[id(value)] = n
        self.alive.append(value)
        return n

    def node(self, value: Any, path: str):
        t = type(value)
        if t in _SCALARS:
            if t is int and not -2**63 <= value < 2**63:
                raise TypeError(f"{path}: integer {value} out of the 64-bit range")
            return value
        if id(value) in self.memo:
            return {"t": "ref", "to": self.memo[id(value)]}
        if isinstance(value, np.ndarray):
            if value.dtype.hasobject:
                raise TypeError(f"{path}: numpy array of dtype {value.dtype} (objects) cannot be checkpointed")
            root = _root(value)
            self.alive.append(root)
            group = self.roots.setdefault(id(root), len(self.roots))
            self.arrays.append(value)
            return {"t": "array", "id": self._id(value), "a": len(self.arrays) - 1, "mem": group}
        if isinstance(value, np.generic):
            if value.dtype.kind not in "biuf":
                raise TypeError(f"{path}: numpy scalar of dtype {value.dtype} cannot be checkpointed")
            return {"t": "np", "dtype": value.dtype.str, "v": value.item()}
        if t is slice:
            return {"t": "slice", "v": [self.node(v, path) for v in (value.start, value.stop, value.step)]}
        if t in (set, frozenset):
            items = sorted(value, key=repr)
            return {"t": t.__name__, "items": [self.node(v, f"{path}{{{i}}}") for i, v in enumerate(items)]}
        if t is tuple:
            return {"t": "tuple", "items": [self.node(v, f"{path}[{i}]") for i, v in enumerate(value)]}
        if t is list:
            n = self._id(value)
            return {"t": "list", "id": n, "items": [self.node(v, f"{path}[{i}]") for i, v in enumerate(value)]}
        if t is dict:
            n = self._id(value)
            items = []
            for k, v in value.items():
                if type(k) not in (str, int):
                    raise TypeError(f"{path}: dict key {k!r} is not a str or an int")
                items.append([k, self.node(v, f"{path}[{k!r}]")])
            return {"t": "dict", "id": n, "items": items}
        if isinstance(value, self.skipped):
            return {"t": "skip", "type": _cls(value)}
        if hasattr(value, "__dict__") and not isinstance(value, _CODE):
            n = self._id(value)
            attrs = vars(value)
            return {"t": "obj", "id": n, "cls": _cls(value),
                    "attrs": {k: self.node(attrs[k], f"{path}.{k}") for k in sorted(attrs)}}
        raise TypeError(f"{path}: a {_cls(value)} cannot be checkpointed (see sphfem_cli.output.snapshot)")


def capture(root: Any, name: str = "sim") -> tuple[dict, list[np.ndarray]]:
    """(tree, arrays) describing every value reachable from `root`; the arrays are not copied."""
    c = _Capture()
    tree = c.node(root, name)
    return tree, c.arrays


def _is_object(value: Any) -> bool:
    """An object of the graph (restored into, never replaced by data), as opposed to data."""
    return value is not _MISSING and not isinstance(
        value, (*_SCALARS, np.ndarray, np.generic, list, tuple, dict, set, frozenset, slice))


class _Restore:
    def __init__(self, arrays: list[np.ndarray]):
        self.arrays = arrays
        self.by_id: dict[int, Any] = {}
        self.group_root: dict[int, int] = {}  # saved "mem" group -> id of the fresh buffer it was copied into
        self.root_group: dict[int, int] = {}
        self.used = [False] * len(arrays)

    def fail(self, path: str, what: str):
        raise SnapshotMismatch(f"{path}: {what}")

    def value(self, node, fresh: Any, path: str) -> Any:
        if _is_object(fresh) and not (isinstance(node, dict) and node.get("t") in ("obj", "ref", "skip")):
            self.fail(path, f"a {_cls(fresh)} in this build, plain data in the checkpoint")
        if not isinstance(node, dict):
            if type(node) not in _SCALARS:
                self.fail(path, f"unexpected value {node!r}")
            return node
        t = node.get("t")
        if t == "ref":
            target = node.get("to")
            if type(target) is not int or target not in self.by_id:
                self.fail(path, "a reference to nothing restored before it")
            return self.by_id[target]
        if t == "array":
            return self._array(node, fresh, path)
        if t == "np":
            dtype = np.dtype(str(node.get("dtype")))
            if dtype.kind not in "biuf" or type(node.get("v")) not in (bool, int, float):
                self.fail(path, f"not a numeric scalar ({dtype})")
            return dtype.type(node["v"])
        if t == "slice":
            parts = node.get("v")
            if not isinstance(parts, list) or len(parts) != 3 or any(p is not None and type(p) is not int
                                                                      for p in parts):
                self.fail(path, "a malformed slice")
            return slice(*parts)
        if t in ("set", "frozenset"):
            items = [self.value(v, _MISSING, path) for v in self._items(node, path)]
            if any(type(v) not in _SCALARS for v in items):
                self.fail(path, "a set of other than numbers and strings")
            return set(items) if t == "set" else frozenset(items)
        if t == "tuple":
            items = self._items(node, path)
            old = fresh if type(fresh) is tuple and len(fresh) == len(items) else ()
            return tuple(self.value(v, old[i] if old else _MISSING, f"{path}[{i}]") for i, v in enumerate(items))
        if t == "list":
            target = fresh if type(fresh) is list else []
            self._remember(node, target, path)
            items = self._items(node, path)
            new = [self.value(v, target[i] if i < len(target) else _MISSING, f"{path}[{i}]")
                   for i, v in enumerate(items)]
            target[:] = new
            return target
        if t == "dict":
            target = fresh if type(fresh) is dict else {}
            self._remember(node, target, path)
            new = {}
            for pair in self._items(node, path):
                if not isinstance(pair, list) or len(pair) != 2 or type(pair[0]) not in (str, int):
                    self.fail(path, "a malformed dict item")
                key, child = pair
                new[key] = self.value(child, target.get(key, _MISSING), f"{path}[{key!r}]")
            target.clear()
            target.update(new)
            return target
        if t == "obj":
            if fresh is _MISSING or _cls(fresh) != node.get("cls"):
                self.fail(path, f"a {node.get('cls')} in the checkpoint, "
                                f"{'nothing' if fresh is _MISSING else 'a ' + _cls(fresh)} in this build")
            self._remember(node, fresh, path)
            attrs = node.get("attrs")
            if not isinstance(attrs, dict):
                self.fail(path, "malformed attributes")
            extra = sorted(set(vars(fresh)) - set(attrs))
            if extra:
                self.fail(path, f"attribute {extra[0]!r} of this build is not in the checkpoint")
            current = vars(fresh)
            params = getattr(fresh, "__dataclass_params__", None)
            bind = object.__setattr__ if params is not None and params.frozen else setattr
            for name, child in attrs.items():
                old = current.get(name, _MISSING)
                new = self.value(child, old, f"{path}.{name}")
                if new is not old:
                    bind(fresh, name, new)
            return fresh
        if t == "skip":
            if fresh is _MISSING or _cls(fresh) != node.get("type"):
                self.fail(path, f"a {node.get('type')} in the checkpoint, "
                                f"{'nothing' if fresh is _MISSING else 'a ' + _cls(fresh)} in this build")
            return fresh
        self.fail(path, f"unknown node type {t!r}")

    def _items(self, node: dict, path: str) -> list:
        items = node.get("items")
        if not isinstance(items, list):
            self.fail(path, "malformed items")
        return items

    def _remember(self, node: dict, value: Any, path: str) -> None:
        n = node.get("id")
        if type(n) is not int or n in self.by_id:
            self.fail(path, "a missing or repeated id")
        self.by_id[n] = value

    def _array(self, node: dict, fresh: Any, path: str) -> np.ndarray:
        index, group = node.get("a"), node.get("mem")
        if type(index) is not int or not 0 <= index < len(self.arrays) or self.used[index] or type(group) is not int:
            self.fail(path, "a malformed array reference")
        self.used[index] = True
        saved = self.arrays[index]
        result = saved
        if (isinstance(fresh, np.ndarray) and fresh.shape == saved.shape and fresh.dtype == saved.dtype
                and fresh.flags.writeable):
            root = id(_root(fresh))
            if self.group_root.get(group, root) == root and self.root_group.get(root, group) == group:
                self.group_root[group] = root
                self.root_group[root] = group
                fresh[...] = saved
                result = fresh
        if result is saved:
            self.group_root.setdefault(group, id(saved))
            self.root_group.setdefault(id(saved), group)
        self._remember(node, result, path)
        return result


def restore(tree: dict, arrays: list[np.ndarray], fresh_root: Any, name: str = "sim") -> None:
    """Overwrite the state of `fresh_root` (built as the checkpointed one was) with `tree` and `arrays`.

    `arrays` must be writeable arrays owning their memory (they may be bound into the graph).
    Raises SnapshotMismatch when the tree does not fit the fresh graph or leaves an array unused.
    """
    r = _Restore(arrays)
    if not isinstance(tree, dict) or tree.get("t") != "obj":
        raise SnapshotMismatch(f"{name}: the checkpoint does not describe an object")
    r.value(tree, fresh_root, name)
    if not all(r.used):
        raise SnapshotMismatch(f"{name}: {r.used.count(False)} array(s) of the checkpoint are referenced nowhere")
