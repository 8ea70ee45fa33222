"""Mesh study: SPH variants of an ALE scene at several particle-spacing ratios, run locally or on
Dask, measured against a reference (errors, GCI, cost) and reported (see docs/mesh-study.md).

- ``derive``   deck derivation (SPH at a ratio, ALE at an element size)
- ``runner``   case folders, status files, the local spawn pool and the Dask executor
- ``metrics``  history errors, three-grid convergence (Richardson, GCI), power-law fits
- ``study``    plan, run, evaluate
- ``report``   terminal table, CSV, JSON, Markdown
- ``plots``    PNGs, and ``sphfem plot``
"""
from .derive import StudyError
from .study import StudyConfig, run_study

__all__ = ["StudyConfig", "StudyError", "run_study"]
