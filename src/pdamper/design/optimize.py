"""Brute-force optimisation of the particle count (paper Sect. 4.2.2).

The objective is the end-effector's amplitude at time ``T`` after release (default 0.8 s),
read from the envelope of the negative peaks; the particle count runs over whole layers.
Every candidate's objective is returned, not only the winner, so that the flatness of the
landscape is visible.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterable, Sized
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING

from pdamper import resources
from pdamper.coupling.simulation import Simulation
from pdamper.damper import ParticleDamper
from pdamper.errors import InputError, check_range, check_whole
from pdamper.models.analytical import AnalyticalDamper

if TYPE_CHECKING:
    from pdamper.structure import SingleDOFStructure
    from pdamper.structure.modal import ModalStructure

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class Candidate:
    """One design: ``particles`` spheres of total ``mass`` [kg]; ``objective`` is the
    amplitude at the objective time [m]."""

    particles: int
    mass: float
    objective: float

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class OptimizationResult:
    """All candidates and the best one (smallest objective)."""

    best: Candidate
    candidates: tuple[Candidate, ...]
    at: float

    def as_dict(self) -> dict:
        return {"best": self.best.as_dict(),
                "candidates": [c.as_dict() for c in self.candidates], "at": self.at}


def optimize_particle_count(
    structure: SingleDOFStructure | ModalStructure,
    damper: ParticleDamper,
    initial_displacement: float,
    at: float,
    model: Callable[[ParticleDamper], object] = AnalyticalDamper,
    counts: Iterable[int] | None = None,
    step: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> OptimizationResult:
    """Find the particle count with the smallest amplitude at time ``at``.

    Parameters
    ----------
    structure
        :class:`~pdamper.structure.SingleDOFStructure`.
    damper
        The damper whose ``count`` is varied (container, spheres, materials kept).
    initial_displacement
        x0 [m] (paper: -58 mm).
    at
        Objective time T [s] (paper: 0.8 s).
    model
        Damper model class (or factory) taking a :class:`ParticleDamper`.
    counts
        Candidate particle counts; default ``0, step, 2 step, ...`` below n_max.
    step
        Increment of the default counts; default one layer (16 in the benchmark).
    progress
        Optional callback ``progress(done, total)``.
    """
    if not isinstance(damper, ParticleDamper):
        raise InputError("damper", "must be a ParticleDamper (e.g. "
                         f"pdamper.parameters.PAPER_DAMPER), got {type(damper).__name__}")
    check_range("optimization.at", at, low=0.0, low_inclusive=False, unit="s")
    if counts is None:
        step = damper.per_layer if step is None else check_whole("optimization.step", step, 1)
        counts = range(0, damper.max_count, step)
    # one period past T so that the envelope at T is bracketed by two peaks
    duration = at + 2.0 / structure.natural_frequency
    if isinstance(counts, Sized):  # what no run can do, judged before the list is read
        one = resources.pseudo_force_cost(duration, 200.0, structure.natural_frequency)
        resources.require(resources.count_cost(
            len(counts), "the optimisation", "candidates",
            bytes_each=resources.BYTES_PER_CANDIDATE, seconds_each=one.seconds,
            field="optimization.counts", usual=12), force=True)
    counts = [check_whole("optimization.counts", n, 0) for n in counts]
    if not counts:
        raise InputError("optimization.counts", "needs at least one particle count")
    out = []
    for k, n in enumerate(counts):
        d = damper.with_count(n)
        res = Simulation(structure, model(d), initial_displacement).run(duration,
                                                                          sample_rate=200.0)
        out.append(Candidate(int(n), d.bed_mass, res.amplitude_at(at)))
        logger.debug("n=%d objective=%.4g m", n, out[-1].objective)
        if progress:
            progress(k + 1, len(counts))
    best = min(out, key=lambda c: c.objective)
    return OptimizationResult(best=best, candidates=tuple(out), at=at)
