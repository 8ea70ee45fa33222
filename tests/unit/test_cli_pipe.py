"""A reader that closes the pipe early (`sphfem schema | head -1`) stops the command quietly with
128 + SIGPIPE, as `cat` would, not with an internal error."""
from __future__ import annotations

import subprocess
import sys


def test_a_closed_pipe_is_not_an_internal_error():
    proc = subprocess.Popen([sys.executable, "-c", "import sys; from sphfem_cli.cli import main; "
                             "sys.argv[0] = 'sphfem'; main()", "schema"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # closed before the command writes: its first write meets a closed pipe
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=60) == 141, err
    assert "internal error" not in err and "Traceback" not in err
