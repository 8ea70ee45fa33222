"""No import circle between the modules of sphfem_cli (issue 14).

The graph: one node per module of ``sphfem_cli/`` (a package is its ``__init__.py``), an edge a -> b for
every import in a that names b, read with ``ast`` from the source (nothing is imported):

- only module-level imports count, including those in module-level ``if`` / ``try`` blocks and class
  bodies (they run when the module is imported); imports inside a function are the deliberate lazy
  imports (run at call time, after every module is loaded) and do not count, nor do imports under
  ``if TYPE_CHECKING:`` (never run);
- relative imports are resolved against the importing module's package; ``from P import x`` is an
  edge to the module ``P.x`` when x is a module of P (``from . import geometry``), else to P itself;
- the implicit import of a module's parent packages is not an edge (a package's ``__init__`` runs
  first in any case, and a parent importing its own children is how packages are built).
"""
from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "sphfem_cli"


def _modules() -> dict[str, Path]:
    """Dotted name -> file of every module of the package ('sphfem_cli.ale' for ale/__init__.py)."""
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(ROOT).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _module_level_imports(body):
    """Import nodes that run when the module is imported (not inside functions, not TYPE_CHECKING)."""
    for node in body:
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        elif isinstance(node, ast.If):
            if not _is_type_checking(node.test):
                yield from _module_level_imports(node.body)
            yield from _module_level_imports(node.orelse)
        elif isinstance(node, ast.ClassDef):
            yield from _module_level_imports(node.body)
        else:
            for field in ("body", "orelse", "finalbody", "handlers"):
                yield from _module_level_imports(getattr(node, field, []) or [])


def import_graph() -> dict[str, set[str]]:
    """module -> the sphfem_cli modules it imports at module level."""
    modules = _modules()
    graph = {}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        edges = set()
        for node in _module_level_imports(ast.parse(path.read_text(), str(path)).body):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            else:
                if node.level:
                    base = package.split(".")
                    base = base[: len(base) - node.level + 1]
                    source = ".".join(base + ([node.module] if node.module else []))
                else:
                    source = node.module or ""
                targets = [f"{source}.{a.name}" if f"{source}.{a.name}" in modules else source for a in node.names]
            for t in targets:
                while t and t not in modules:  # ``import sphfem_cli.a.b`` of a name below a module
                    t = t.rpartition(".")[0]
                if t and t != name:
                    edges.add(t)
        graph[name] = edges
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle [a, b, ..., a] of the graph, or None (depth-first search, iterative)."""
    state = dict.fromkeys(graph, 0)  # 0 new, 1 on the path, 2 done
    for root in sorted(graph):
        if state[root]:
            continue
        path = [root]
        stack = [iter(sorted(graph[root]))]
        state[root] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                state[path.pop()] = 2
                stack.pop()
            elif state[nxt] == 1:
                return path[path.index(nxt):] + [nxt]
            elif state[nxt] == 0:
                state[nxt] = 1
                path.append(nxt)
                stack.append(iter(sorted(graph[nxt])))
    return None


def test_the_graph_is_read():
    graph = import_graph()
    assert "sphfem_cli.ale.lagrange" in graph["sphfem_cli.ale.axisymmetric"]  # from .lagrange import ...
    assert "sphfem_cli.fem.geometry" in graph["sphfem_cli.ale.lagrange"]  # from ..fem.geometry import ...
    assert "sphfem_cli.ale.kernels" in graph["sphfem_cli.ale.system"]  # from . import kernels as K: the module
    assert "sphfem_cli.materials.ids" in graph["sphfem_cli.materials.tables"]  # from . import ids
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b"}, "b": set()}) is None


def test_no_import_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import circle: " + " -> ".join(cycle)
