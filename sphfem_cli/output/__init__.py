"""Result files: XDMF/HDF5 field time series (:mod:`.xdmf`) and CSV time histories (:mod:`.history`)."""
from sphfem_cli.output.history import HistoryWriter
from sphfem_cli.output.xdmf import GridStep, XdmfWriter

__all__ = ["GridStep", "HistoryWriter", "XdmfWriter"]
