"""The progress display of ``pdamper paper``: live on a terminal (stderr), saying what runs
(the step, each figure, the DEM map's points done of total); absent where stderr is a pipe,
so that neither the ``--json`` output nor a log carries it."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys

import pytest

from proc import command, env

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="pseudo-terminals are POSIX")

#: The figures of ``paper --no-dem``.
FIGURES = ("fig2_materials_cor.png", "fig4_trajectories.png", "fig5a_motion_modes.png",
           "fig5c_loss_factor.png", "fig7_trajectory.png", "fig8_damping_ratio.png",
           "fig9_optimization.png")
#: a small Fig. 5a/5c grid: a run takes a few seconds
SCENARIO = '[map]\nfrequency = "2Hz:20Hz:5"\namplitude = "2mm:200mm:6"\n'


def _paper(tmp_path, *args, stderr_on_terminal: bool):
    """Run ``pdamper paper --no-dem`` with stdout a pipe and stderr a pseudo-terminal (or a
    pipe); returns (exit status, stdout, what reached stderr)."""
    import pty

    scenario = tmp_path / "s.toml"
    scenario.write_text(SCENARIO)
    argv = command("paper", "--no-dem", "--scenario", scenario, "--out", tmp_path / "out", *args)
    e = env(TERM="xterm", COLUMNS="160")
    if not stderr_on_terminal:
        p = subprocess.run(argv, stdin=subprocess.DEVNULL, capture_output=True, env=e,
                           timeout=300)
        return p.returncode, p.stdout.decode(), p.stderr.decode()
    master, slave = pty.openpty()
    try:
        p = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                             stderr=slave, env=e)
    finally:
        os.close(slave)
    seen = bytearray()
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:  # EIO: the child closed the terminal
            break
        if not chunk:
            break
        seen += chunk
    out = p.stdout.read()
    p.stdout.close()
    code = p.wait(timeout=300)
    os.close(master)
    return code, out.decode(), seen.decode(errors="replace")


def test_a_terminal_sees_each_step_and_each_figure_and_the_json_output_none(tmp_path):
    code, out, terminal = _paper(tmp_path, "--json", stderr_on_terminal=True)
    assert code == 0, terminal
    # each step is drawn when it starts: the model runs, each figure, the files
    for step in ("Fig. 4: bed trajectories", "Sect. 4.2.2: optimisation",
                 *(f"writing {name}" for name in FIGURES), "writing report.html"):
        assert step in terminal, step
    assert "\x1b[" in terminal  # drawn in place, and erased when done
    # stdout: exactly one JSON document, nothing of the display
    assert json.loads(out)["rows"] == 24
    assert "\x1b" not in out and "\r" not in out


def test_no_progress_in_pipes(tmp_path):
    code, out, err = _paper(tmp_path, stderr_on_terminal=False)
    assert code == 0, err
    assert err == ""  # neither the display nor its control characters
    assert "reported numbers agree" in out and "\x1b" not in out


def test_display_shows_the_step_and_the_dem_map_points():
    """The display itself, on a terminal-like console: the current step, and the DEM map's
    points as done/total."""
    from rich.console import Console

    from pdamper.cli.paper import _Progress

    buf = io.StringIO()
    console = Console(file=buf, force_terminal=True, width=120, color_system=None)
    with _Progress(console) as prog:
        prog.step("compiling the DEM kernels (gear; first run only, then cached)")
        prog.map_points(0, 35)
        prog.map_points(12, 35)
        shown = buf.getvalue()
    assert "compiling the DEM kernels" in shown
    assert "DEM map points" in shown and "12/35" in shown


def test_display_is_off_where_stderr_is_no_terminal():
    from rich.console import Console

    from pdamper.cli.paper import _Progress

    buf = io.StringIO()
    with _Progress(Console(file=buf)) as prog:  # a StringIO is no terminal
        prog.step("Fig. 4: bed trajectories")
        prog.map_points(1, 2)
        prog._progress.refresh()
    assert buf.getvalue() == ""
