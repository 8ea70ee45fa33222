"""What a run writes about itself (run.log), and what an output write failure means for the exit code.

Exit codes for output failures are sysexits(3)'s: EX_CANTCREAT (73) when the output folder or a file
in it cannot be created, EX_IOERR (74) when a write fails while the run goes on.
"""
from __future__ import annotations

import errno
import os
import platform
import re
import socket
import sys
import time
from pathlib import Path

from .. import __version__

from ..driver import EXIT_CANTCREAT, EXIT_IOERR

# errno values that mean a file or folder cannot be created (EX_CANTCREAT); other OSErrors are EX_IOERR
_CANNOT_CREATE = {errno.EACCES, errno.EPERM, errno.EROFS, errno.ENOENT, errno.ENOTDIR, errno.EISDIR,
                  errno.EEXIST, errno.ENAMETOOLONG, errno.ELOOP}


def errno_of(err: OSError) -> int | None:
    """The errno of an OSError; h5py gives the C library's only in its message ("errno = 28")."""
    if err.errno is not None:
        return err.errno
    m = re.search(r"errno = (\d+)", str(err))
    return int(m.group(1)) if m else None


def io_failure(err: OSError, creating: bool) -> tuple[int, str]:
    """(exit code, one-line reason) of an OSError met while writing output (`creating`: before the
    output files exist, any failure is EX_CANTCREAT)."""
    number = errno_of(err)
    reason = os.strerror(number) if number is not None else (err.strerror or str(err).split("\n")[0])
    where = f"{err.filename}: " if getattr(err, "filename", None) else ""
    if creating or number in _CANNOT_CREATE:
        return EXIT_CANTCREAT, f"{where}{reason}"
    return EXIT_IOERR, f"{where}{reason}"


class RunLog:
    """run.log (UTF-8). Opening it may raise OSError; later writes never do: the first failure is kept
    in `error` and the log writes nothing more."""

    def __init__(self, path: Path, deck: Path, append: bool = False):
        self.error: OSError | None = None
        self.file = path.open("a" if append else "w", encoding="utf-8")
        self.file.write(
            f"sphfem {__version__}\ncommand: {' '.join(sys.argv)}\ndeck: {deck.resolve()}\n"
            f"host: {socket.gethostname()} ({platform.platform()}, Python {platform.python_version()})\n"
            f"started: {time.strftime('%Y-%m-%d %H:%M:%S')}\n"
        )
        self.file.flush()

    def write(self, text: str) -> None:
        if self.error is not None or self.file.closed:
            return
        try:
            self.file.write(text)
            self.file.flush()
        except OSError as err:
            self.error = err

    def close(self, status: str, message: str, wall: float, steps: int, threads: int) -> None:
        self.write(f"threads: {threads}\nsteps: {steps}\nwall time: {wall:.3f} s\nstatus: {status}\n"
                   + (f"message: {message}\n" if message else ""))
        try:
            self.file.close()
        except OSError as err:
            self.error = self.error or err
