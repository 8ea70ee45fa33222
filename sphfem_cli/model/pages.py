"""4 kB pages for the arrays of the ALE set-up (``set_up_pages``: ``build.build_model``'s ALE part, ``AleSystem``).

numpy advises the kernel to back every array of 4 MB and more with transparent huge pages (madvise MADV_HUGEPAGE).
Where transparent huge pages are "madvise" and their defrag "madvise" (this machine), a 2 MB first touch may stall
in direct compaction: the 960^2 ALE set-up (two materials, some 0.75 GB of first touches) spent 1.0-7 s of system
time with numpy's advice against 0.6-0.9 s without it, while the time loop stepped as fast on the arrays the
set-up had made with 4 kB pages (numpy's advice on again for the steps: CPU time of the steps 0.96-1.02 of the
all-huge-page run's, medians of 3 rounds, two runs); with the advice off for the whole process the loop was up to
22 % slower (benchmarks/README.md, "The ALE 960^2 set-up's memory, and huge pages in the time loop"; the figures:
``benchmarks/ale_passes.py --madvise``, ``benchmarks/startup.py``).
"""
from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def set_up_pages() -> Iterator[None]:
    """numpy's huge-page advice off inside the block, back to its former setting after (a no-op where numpy has no
    such switch)."""
    try:
        from numpy._core.multiarray import _set_madvise_hugepage
    except ImportError:  # numpy < 2 names it numpy.core.multiarray; without it there is nothing to switch
        try:
            from numpy.core.multiarray import _set_madvise_hugepage
        except ImportError:
            yield
            return
    previous = _set_madvise_hugepage(False)
    try:
        yield
    finally:
        _set_madvise_hugepage(previous)
