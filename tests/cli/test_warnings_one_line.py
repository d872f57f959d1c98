"""Python warnings reach the user of the command line as one line each, without the
source file, line number and code line of Python's default format."""

from __future__ import annotations

import subprocess
import sys
import warnings

from proc import env


def test_a_warning_in_a_command_is_one_line_without_source_paths(capsys):
    from pdamper.cli import _quiet
    from pdamper.dem.inputs import LargeOverlapWarning

    with _quiet.scope():
        warnings.warn("DEM overlaps beyond 5 % of the radius", LargeOverlapWarning,
                      stacklevel=1)
    err = capsys.readouterr().err
    assert err == "warning: DEM overlaps beyond 5 % of the radius (LargeOverlapWarning)\n"
    assert ".py" not in err


def test_python_s_own_format_is_back_after_the_command(capsys):
    from pdamper.cli import _quiet

    with _quiet.scope():
        pass
    assert warnings.showwarning is not _quiet._one_line


def test_a_numpy_warning_of_a_run_is_one_line():
    """In a child process, as a user runs it: numpy's RuntimeWarning raised inside a command
    in the scope of a command line prints one line."""
    code = (
        "import numpy as np, sys\n"
        "from pdamper.cli import _quiet\n"
        "with _quiet.scope():\n"
        "    np.log(np.array([-1.0]))\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env=env(), timeout=120)
    lines = p.stderr.splitlines()
    assert p.returncode == 0
    assert lines == ["warning: invalid value encountered in log (RuntimeWarning)"], p.stderr
