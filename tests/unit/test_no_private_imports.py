"""No private name crosses a folder: what two physics folders share lives under a public name
(fem/geometry.py, materials/kernels.eos_state, model/ale_build.fill_region)."""
from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "sphfem_cli"


def _folder(module: tuple[str, ...]) -> str:
    return module[0] if len(module) > 1 else ""  # "" for the package's top-level modules


def test_no_private_name_is_imported_from_another_folder():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        package = parts[:-1]
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.ImportFrom) or not node.level:
                continue
            base = package[: len(package) - node.level + 1] if node.level > 1 else package
            target = (*base, *(node.module.split(".") if node.module else ()))
            if _folder(target) == _folder(parts):
                continue
            found += [f"{'/'.join(parts)}.py:{node.lineno}: {a.name} from {'.'.join(target)}"
                      for a in node.names if a.name.startswith("_") and not a.name.startswith("__")]
    assert not found, "\n".join(found)
