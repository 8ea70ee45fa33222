"""sphfem: explicit-dynamics fluid-structure interaction (FEM, ALE/VOF, SPH) from a YAML deck."""
from __future__ import annotations

import hashlib
import os
from pathlib import Path

__version__ = "0.1.0"


def _kernel_source_hash() -> str:
    """Hash of every source file in the package.

    numba's on-disk cache is keyed by the caller's own source only, so editing a callee leaves its
    callers' cached machine code stale. Keying the cache directory by the hash of all sources makes
    any edit start a fresh cache.
    """
    digest = hashlib.sha1(__version__.encode())
    root = Path(__file__).parent
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


if "NUMBA_CACHE_DIR" not in os.environ:
    _base = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
    os.environ["NUMBA_CACHE_DIR"] = str(_base / "sphfem" / f"numba-{_kernel_source_hash()}")
