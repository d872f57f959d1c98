"""The DEM driver (:mod:`pdamper.dem.driver`): one ``advance`` loop, the controllers
around it, the kernels entered with named bundles; the one summary of a run
(:meth:`pdamper.dem.DEMResult.summary`); the size limits of the engine's modules."""

from __future__ import annotations

import ast
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import pdamper.dem
from dem_inputs import engine, lattice
from pdamper.dem import HarmonicMotion
from pdamper.dem.driver import (
    AUTO_WINDOW,
    AutoSwitch,
    ChunkSizer,
    Controller,
    StopRule,
    TransientTolerance,
    advance,
)
from pdamper.dem.kernels import state as K
from pdamper.dem.result import WALL_TIME_KEYS

DEM = Path(pdamper.dem.__file__).parent


# ------------------------------------------------------------------ controllers
def test_chunk_sizer_whole_phase_fixed_sample_and_measured_rate():
    assert ChunkSizer(math.inf).target(0, 100) == 100
    one = ChunkSizer(math.inf, one_sample=True)
    one.measured(2, 1.0)
    assert one.target(10, 100) == 12  # one sample per call, whatever the rate
    sized = ChunkSizer(0.25)
    assert sized.target(0, 100) == 2  # the first chunk: two landings
    sized.measured(2, 0.25 / 8)  # 16 landings fit 0.25 s, but at most 4x the last chunk
    assert sized.target(2, 100) == 10
    sized.measured(8, 0.25)  # 8 landings took 0.25 s
    assert sized.target(10, 100) == 18
    sized.measured(2, 10.0)  # slow: never below two landings
    assert sized.target(18, 100) == 20


def test_stop_rule_ends_chunks_on_whole_cycles_and_asks_only_there():
    asked = []
    rule = StopRule(lambda j: asked.append(j) or j >= 40, cycle=20, j_end=100)
    assert rule.limit(0, 35) == 20 and rule.limit(20, 100) == 100 and rule.limit(25, 90) == 40
    assert not rule.stop(30) and asked == []  # not a whole cycle: not asked
    assert not rule.stop(20) and rule.stop(40) and asked == [20, 40]
    assert not rule.stop(100)  # the end of the phase is no stop


def test_transient_tolerance_holds_until_its_landing():
    stp = K.Stepping(*(0,) * len(K.Stepping._fields))._replace(tol=1e-6)
    phase = SimpleNamespace(stepping=stp)
    tt = TransientTolerance(phase, end=40, transient=1e-4, tolerance=1e-6)
    assert phase.stepping.tol == 1e-4
    assert tt.limit(0, 100) == 40 and tt.limit(40, 100) == 100
    tt.landed(20)
    assert phase.stepping.tol == 1e-4
    tt.landed(40)
    assert phase.stepping.tol == 1e-6


def test_advance_is_one_loop_that_every_controller_shapes():
    """A controller's limit ends the chunks where it must decide; its stop ends the phase;
    what one chunk did is reported before the next (here a fake kernel: the loop knows
    the kernels only through KERNELS)."""
    from pdamper.dem import driver

    calls = []

    class Fake:
        @staticmethod
        def advance(run, phase, j_stop):
            calls.append(j_stop)

    class Every30(Controller):
        def __init__(self):
            self.seen = []

        def limit(self, j, target):
            return min(target, (j // 30 + 1) * 30)

        def landed(self, j):
            self.seen.append(j)

        def stop(self, j):
            return j >= 90

    phase = SimpleNamespace(kernel="fake")
    c = Every30()
    old = dict(driver.KERNELS)
    driver.KERNELS["fake"] = Fake
    try:
        j = advance(None, phase, 200, ChunkSizer(math.inf), (c,), check=lambda p: None)
    finally:
        driver.KERNELS.clear()
        driver.KERNELS.update(old)
    assert calls == [30, 60, 90] and c.seen == [30, 60, 90] and j == 90


# ------------------------------------------------------------------ real runs
def test_the_auto_switch_hands_over_at_its_judgement_landings():
    """``auto`` with an infinite cost ratio hands over at the first judgement, probes Gear
    one window later and hands back: the hand-overs happen on the window's landings
    whatever the chunking (the same counts in one call and in the smallest chunks)."""
    runs = [engine(lattice(16), motion=HarmonicMotion(0.02, 15.0), integrator="auto",
                   settle_time=0.0, auto_cost_ratio=math.inf).run(
        0.02, sample_rate=2000.0, chunk_seconds=cs) for cs in (math.inf, 1e-9)]
    half = 0.5 / (15.0 * round(2000.0 / 15.0))  # the landing grid of the run
    window = 2 * max(1, round(AUTO_WINDOW / (2 * half)))  # landings of a judgement window
    for res in runs:
        assert res.integrator_switches >= 3
        assert res.integrator_switch_time == pytest.approx(window * half, rel=1e-12)
    assert runs[0].steps == runs[1].steps
    assert np.array_equal(runs[0].kinetic_energy, runs[1].kinetic_energy)
    assert AutoSwitch.__mro__[1] is Controller


def test_summary_names_the_excitation_the_settling_and_their_sum():
    sim = engine(lattice(16), motion=HarmonicMotion(0.01, 20.0), integrator="gear",
                 settle_time=0.03)
    own = sim.run(0.05, sample_rate=2000.0)
    reused = sim.run(0.05, sample_rate=2000.0, start=sim.settle())
    s, r = own.summary(), reused.summary()
    assert s["excitation_steps"] == own.steps > 0
    assert s["settle_steps"] == own.settle_steps > 0
    assert s["steps"] == s["total_steps"] == own.steps + own.settle_steps
    assert s["excitation_wall_seconds"] == own.wall_seconds
    assert s["wall_seconds"] == s["total_wall_seconds"] == own.wall_seconds + own.settle_seconds
    assert r["settle_steps"] == 0 and r["settle_seconds"] == 0.0 and r["settle_reused"]
    # the same excitation, to the bit
    assert r["total_steps"] == r["steps"] == r["excitation_steps"] == s["excitation_steps"]
    for key in set(s) - set(WALL_TIME_KEYS) - {"settle_steps", "steps", "total_steps",
                                                "settle_reused"}:
        assert s[key] == r[key], key
    assert all(isinstance(v, int | float | bool | str) for v in s.values())


# ------------------------------------------------------------------ structure
def _functions(path: Path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            numba = any("jit" in ast.unparse(d) for d in node.decorator_list)
            yield node, node.end_lineno - node.lineno + 1, numba


def test_the_engine_reads_in_short_units():
    """dem/simulation.py under 700 lines; no function of dem/ over 80 lines outside the
    numba kernels."""
    assert len((DEM / "simulation.py").read_text().splitlines()) < 700
    long = [f"{p.relative_to(DEM)}:{node.name} ({n} lines)" for p in DEM.rglob("*.py")
            for node, n, numba in _functions(p) if n > 80 and not numba]
    assert long == []


def test_kernels_are_entered_with_named_bundles():
    """No positional slices of an argument tuple into a kernel (``*a[:12]``): every
    kernel call outside the kernels names what it passes."""
    for path in DEM.glob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Call):
                for arg in node.args:
                    assert not (isinstance(arg, ast.Starred)
                                and isinstance(arg.value, ast.Subscript)), (
                        f"{path.name}:{node.lineno}: {ast.unparse(node)[:80]}")
