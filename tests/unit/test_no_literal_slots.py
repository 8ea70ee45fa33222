"""No literal index into a parameter, history or settings row outside the module that declares its slots.

A material row's slot 5 is a yield stress, a Johnson-Cook A or a viscosity depending on the model
(issue 14), so every reader names its slots through ``sphfem_cli/materials/slots.py``. The check
parses every module of the package (``ast``) and reports each subscript of a row whose slot index
is a number: ``p[5]``, ``q[EOS_OFFSET + 1]``, ``st.hist[:, 0]``, ``model.material_param[m][0]``,
``p[5:9]``. What counts as a row:

- ``ROW_NAMES``: variables and attributes that hold a row or a table of rows (one row per
  material, element, ...; the slot is the last index) wherever they appear;
- ``ROW_VARIABLES``: names that hold one row in one module (``p`` is a row in the constitutive
  kernels but a point in the contact kernels);
- any name that a function indexes with a slot name (``row[P_EOS_TYPE]`` makes ``row`` a row there:
  ``SLOT_NAME``);
- any local name assigned from a row (``p = mat_param[m]``, ``q = np.ascontiguousarray(row[EOS_OFFSET:])``).

To cover a new row (a new settings vector or table), add its name to ``ROW_NAMES`` and
its declaration module to ``DECLARATIONS``. Coordinate axes (``x[:, 0]``) and the 6-vector stress
components are not slots and are not checked.
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "sphfem_cli"

DECLARATIONS = ("materials/slots.py", "sph/slots.py")
"""Modules (relative to the package) that declare slots and may write their numbers."""

ROW_NAMES = frozenset({
    "material_param", "mat_param", "params", "mat_q",  # material rows (M, NPARAM), EOS rows (M, NQ)
    "hist",  # history rows (E, NHIST)
    "settings_f", "settings_i", "grid_f", "grid_i",  # SPH settings and cell-grid vectors (sph/slots.py)
    "sec_param",  # section table (fem/slots.py SEC_* columns)
})

ROW_VARIABLES = {
    "materials/kernels.py": frozenset({"p", "q", "hist"}),
    "materials/tables.py": frozenset({"p", "q"}),
    "materials/plausibility.py": frozenset({"row"}),
    "ale/lagrange.py": frozenset({"q"}),
    "ale/fill.py": frozenset({"q", "row"}),
    "ale/reference.py": frozenset({"q"}),
}

SLOT_NAME = re.compile(r"^((P|Q|H|SF|SI|GF|GI|SEC)_[A-Z0-9_]+|EOS_OFFSET)$")
"""Names of slots (materials/slots.py P_, Q_, H_; sph/slots.py settings SF_, SI_ and grid GF_, GI_; the
section table SEC_)."""

_ROW_CALLS = frozenset({"asarray", "ascontiguousarray", "array", "copy"})


def _literal(node: ast.AST) -> bool:
    """A number, or an expression with a number in it (``EOS_OFFSET + 1``)."""
    return any(isinstance(n, ast.Constant) and isinstance(n.value, int) and not isinstance(n.value, bool)
               for n in ast.walk(node))


def _slot(index: ast.AST) -> ast.AST:
    return index.elts[-1] if isinstance(index, ast.Tuple) and index.elts else index


def _names_slot(index: ast.AST) -> bool:
    slot = _slot(index)
    parts = (slot.lower, slot.upper) if isinstance(slot, ast.Slice) else (slot,)
    for part in parts:
        for n in ast.walk(part) if part is not None else ():
            name = n.id if isinstance(n, ast.Name) else n.attr if isinstance(n, ast.Attribute) else ""
            if SLOT_NAME.match(name):
                return True
    return False


def _is_literal_slot(index: ast.AST) -> bool:
    slot = _slot(index)
    if isinstance(slot, ast.Slice):  # p[5:9]; a named range end such as F_GZ + 1 is allowed
        return any(isinstance(b, ast.Constant) and isinstance(b.value, int) for b in (slot.lower, slot.upper))
    return _literal(slot)


class _Finder(ast.NodeVisitor):
    def __init__(self, variables: frozenset[str]):
        self.scopes: list[set[str]] = [set(variables)]
        self.hits: list[tuple[int, str]] = []

    def _is_row(self, node: ast.AST) -> bool:
        if isinstance(node, ast.Name):
            return node.id in ROW_NAMES or node.id in self.scopes[-1]
        if isinstance(node, ast.Attribute):
            return node.attr in ROW_NAMES
        if isinstance(node, ast.Subscript):  # a row of a table, or a slice of a row
            return self._is_row(node.value)
        if isinstance(node, ast.Call):  # np.ascontiguousarray(row[EOS_OFFSET:]) and the like
            fn = node.func
            name = fn.attr if isinstance(fn, ast.Attribute) else getattr(fn, "id", "")
            return name in _ROW_CALLS and bool(node.args) and self._is_row(node.args[0])
        return False

    def visit_FunctionDef(self, node: ast.FunctionDef) -> None:
        named = {n.value.id for n in ast.walk(node)
                 if isinstance(n, ast.Subscript) and isinstance(n.value, ast.Name) and _names_slot(n.slice)}
        self.scopes.append(self.scopes[-1] | named)
        self.generic_visit(node)
        self.scopes.pop()

    visit_AsyncFunctionDef = visit_FunctionDef

    def visit_Assign(self, node: ast.Assign) -> None:
        self.generic_visit(node)
        targets = [t for t in node.targets if isinstance(t, ast.Name)]
        if targets and self._is_row(node.value):
            self.scopes[-1].update(t.id for t in targets)

    def visit_Subscript(self, node: ast.Subscript) -> None:
        if self._is_row(node.value) and _is_literal_slot(node.slice):
            self.hits.append((node.lineno, ast.unparse(node)))
        self.generic_visit(node)


def literal_slots(source: str, module: str = "") -> list[tuple[int, str]]:
    """``(line, expression)`` of every literal-index subscript of a row in ``source``."""
    finder = _Finder(ROW_VARIABLES.get(module, frozenset()))
    finder.visit(ast.parse(source))
    return finder.hits


def test_the_finder_flags_literal_slots_and_passes_named_ones():
    source = """
def f(p, q, hist, x, st, model, m, mat_param, row):
    a = p[5] + q[EOS_OFFSET + 1] + st.hist[:, 0] + model.material_param[m][0]
    p[5:9] = [1.0, 2.0, 3.0, 4.0]
    r = mat_param[m]
    b = r[3] + np.ascontiguousarray(mat_param[m, EOS_OFFSET:])[1]
    ok = x[:, 0] + p[P_RHO0] + hist[e, H_EPS] + q[EOS_OFFSET:][Q_E0] + st.settings_f[SF_GX:SF_GZ + 1] + row[0]
    c = st.grid_i[1] + settings_f[SF_ALPHA]
"""
    hits = [expr for _, expr in literal_slots(source, "materials/kernels.py")]
    assert hits == ["p[5]", "q[EOS_OFFSET + 1]", "st.hist[:, 0]", "model.material_param[m][0]", "p[5:9]",
                    "r[3]", "np.ascontiguousarray(mat_param[m, EOS_OFFSET:])[1]", "st.grid_i[1]"]
    point = "def project(p, a0, t0):\n    return (p[0] - a0) * t0\n"  # p is a point here, not a row
    assert literal_slots(point, "contact/kernels.py") == []
    assert literal_slots(point.replace("t0\n", "t0 * p[P_RHO0]\n"), "contact/kernels.py") == [(2, "p[0]")]


def test_no_literal_slot_index_outside_the_declarations():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        module = path.relative_to(PACKAGE).as_posix()
        if module in DECLARATIONS:
            continue
        found += [f"sphfem_cli/{module}:{line}: {expr}" for line, expr in literal_slots(path.read_text(), module)]
    assert not found, "literal slot indices (name them in materials/slots.py or sph/slots.py):\n" + "\n".join(found)
