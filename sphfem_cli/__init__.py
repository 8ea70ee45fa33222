"""sphfem: explicit-dynamics fluid-structure interaction (FEM, ALE/VOF, SPH) from a YAML deck."""
from __future__ import annotations

import hashlib
import os
from pathlib import Path

__version__ = "0.1.0"


def _kernel_source_hash() -> str:
    """Hash of every source file of the package that defines numba kernels or constants they fold.

    numba's on-disk cache is keyed by the caller's own source only, so editing a callee leaves its
    callers' cached machine code stale; the same holds for a module-level int a kernel reads, which
    numba folds in as a constant. Keying the cache directory by the hash of all kernel sources and
    of the modules that mark themselves ``__numba_folded__`` (``materials/slots.py``) makes any such
    edit start a fresh cache, while edits elsewhere keep it.
    """
    digest = hashlib.sha1(__version__.encode())
    root = Path(__file__).parent
    for path in sorted(root.rglob("*.py")):
        source = path.read_bytes()
        if b"njit" in source or b"__numba_folded__" in source:
            digest.update(path.relative_to(root).as_posix().encode())
            digest.update(source)
    return digest.hexdigest()[:16]


if "NUMBA_CACHE_DIR" not in os.environ:
    _base = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
    os.environ["NUMBA_CACHE_DIR"] = str(_base / "sphfem" / f"numba-{_kernel_source_hash()}")
