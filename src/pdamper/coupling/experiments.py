"""Level III experiments: what is done to the structure carrying the damper.

An experiment is handed, with the structure and the damper model, to
:class:`~pdamper.coupling.simulation.Simulation` (the model / experiment / solver split of
PyBaMM: the structure and the damper are the model, the experiment says what is done to
them, the coupling strategy of the damper model, :data:`pdamper.coupling.registry.COUPLINGS`,
is the solver):

- :class:`Release`: the free decay of Sect. 4.2, released from rest at a deflection
  (:class:`~pdamper.coupling.results.FreeVibrationResult`);
- :class:`Loading`: a load history, a force at the structure's load point or a base
  acceleration (:class:`~pdamper.coupling.loads.LoadHistory`), or any load that writes one
  (:class:`~pdamper.coupling.loads.RunUp`, the unbalance of a machine run up or down)
  (:class:`~pdamper.coupling.loads.LoadResponse`);
- :class:`HarmonicSweep`: the forced response to a harmonic force, unbalance or base
  motion over frequencies, stepped sines up and down and harmonic balance
  (:class:`~pdamper.coupling.frf.FRFResult`).

A new kind of experiment is one subclass of :class:`Experiment` (its ``name`` the entry of
the strategies' ``answers`` it needs); a new load type is one class with a ``history()``
method that returns the :class:`~pdamper.coupling.loads.LoadHistory` (as
:class:`~pdamper.coupling.loads.RunUp` does), handed to :class:`Loading`.

Examples
--------
>>> from pdamper.coupling import Simulation
>>> from pdamper.models import AnalyticalDamper
>>> from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
>>> decay = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER),
...                    Release(-0.058, duration=2.0)).solve()
>>> 0.005 < decay.final_amplitude < 0.015
True
>>> sweep = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER.with_count(0)),
...                    HarmonicSweep([4.0, 5.0], force=2.0, direction="none")).solve()
>>> sweep.frequency.tolist()
[4.0, 5.0]
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from pdamper.coupling.registry import HARMONIC_SWEEP, LOAD_HISTORY, RELEASE, Coupling
from pdamper.errors import InputError, check_range


class Experiment:
    """What is done to the structure carrying the damper (module docstring).

    Subclasses set ``name`` (the experiment the coupling strategies declare in their
    ``answers``) and implement :meth:`solve`; :meth:`prepare` checks, before any run, that
    the strategy answers the experiment on the structure.
    """

    name: ClassVar[str] = ""

    def prepare(self, strategy: Coupling, model: Any, structure: Any) -> Any:
        """The structure the strategy runs this experiment on (a one-mode structure may run
        as its 1-DOF equivalent); InputError where it cannot."""
        return strategy.structure_for(self.name, model, structure)

    def solve(self, strategy: Coupling, model: Any, structure: Any) -> Any:
        """Run the experiment on ``structure`` (as :meth:`prepare` returned it)."""
        raise NotImplementedError


@dataclass(frozen=True)
class Release(Experiment):
    """Free decay: the structure released from rest with its release point at
    ``initial_displacement`` [m] from the static equilibrium (the paper's -58 mm, Sect. 4.2),
    simulated for ``duration`` [s] and sampled at ``sample_rate`` [Hz].

    ``duration`` may be left to :meth:`Simulation.run`
    (:class:`~pdamper.coupling.simulation.Simulation`).
    """

    initial_displacement: float
    duration: float | None = None
    sample_rate: float = 2000.0
    name: ClassVar[str] = RELEASE

    def __post_init__(self) -> None:
        object.__setattr__(self, "initial_displacement", check_range(
            "structure.initial_displacement", self.initial_displacement, high=0.0,
            high_inclusive=False, unit="m"))
        if self.duration is not None:
            check_range("simulation.duration", self.duration, low=0.0, low_inclusive=False,
                        unit="s")
        check_range("simulation.sample_rate", self.sample_rate, low=0.0, low_inclusive=False,
                    unit="Hz")

    def prepare(self, strategy: Coupling, model: Any, structure: Any) -> Any:
        from pdamper import resources

        structure = super().prepare(strategy, model, structure)
        # the physics limits of every Level III run, whichever the model (a design study's
        # candidate, the API): the release at the (first) natural frequency
        resources.check_release(model.damper, structure.natural_frequency,
                                self.initial_displacement, contact_law=model.contact_law)
        return structure

    def solve(self, strategy: Coupling, model: Any, structure: Any) -> Any:
        if self.duration is None:
            raise InputError("simulation.duration", "the release needs a duration [s]: "
                             "Release(x0, duration=...) or Simulation.run(duration)")
        return strategy(model, structure, self.duration, self.initial_displacement,
                        self.sample_rate)


@dataclass(frozen=True)
class Loading(Experiment):
    """A load history on the structure from rest: ``load`` a
    :class:`~pdamper.coupling.loads.LoadHistory` (a force at the load point or a base
    acceleration), or an object with a ``history()`` method that writes one (a
    :class:`~pdamper.coupling.loads.RunUp`), over the record plus a free ``tail`` [s],
    sampled at ``sample_rate`` [Hz] (:func:`pdamper.coupling.loads.run_load`).

    The experiment form of a load history (the record itself keeps the name
    :class:`~pdamper.coupling.loads.LoadHistory`).
    """

    load: Any
    sample_rate: float = 2000.0
    tail: float = 0.0
    name: ClassVar[str] = LOAD_HISTORY

    def __post_init__(self) -> None:
        from pdamper.coupling.loads import LoadHistory

        if not isinstance(self.load, LoadHistory) and not callable(
                getattr(self.load, "history", None)):
            raise InputError("load", "must be a LoadHistory or a load with a history() "
                             f"(e.g. a RunUp), got {type(self.load).__name__}")
        check_range("simulation.sample_rate", self.sample_rate, low=0.0, low_inclusive=False,
                    unit="Hz")
        check_range("load.tail", self.tail, low=0.0, unit="s")

    @property
    def history(self) -> Any:
        """The :class:`~pdamper.coupling.loads.LoadHistory` that is run."""
        from pdamper.coupling.loads import LoadHistory

        return self.load if isinstance(self.load, LoadHistory) else self.load.history()

    def prepare(self, strategy: Coupling, model: Any, structure: Any) -> Any:
        from pdamper.coupling.loads import load_strategy

        load_strategy(model, structure)  # the coupling's own check of the structure
        return structure

    def solve(self, strategy: Coupling, model: Any, structure: Any) -> Any:
        return strategy.load(model, structure, self.history, self.sample_rate, self.tail)


@dataclass(frozen=True)
class HarmonicSweep(Experiment):
    """The forced response to a harmonic load over ``frequencies`` [Hz]
    (:func:`pdamper.coupling.frf.frequency_response`): the linear FRF, harmonic balance
    where the coupling has it, and stepped sines in ``direction`` (``"up"``, ``"down"``,
    ``"both"``, ``"none"``).

    The load is ``load`` (a :class:`~pdamper.coupling.frf.HarmonicLoad`) or exactly one of
    ``force`` [N] (at the load point), ``unbalance`` ``m e`` [kg m] (the force
    ``m e Omega^2`` at the load point) and ``base`` [m] (base displacement; with
    ``acceleration=True`` [m/s^2]). Without ``frequencies`` the sweep spans every mode of
    the structure, resolved for its damping (:func:`pdamper.coupling.frf.default_frequencies`).
    ``strokes``, ``max_cycles``, ``criterion`` and ``progress`` are
    :func:`~pdamper.coupling.frf.frequency_response`'s.
    """

    frequencies: Sequence[float] | np.ndarray | None = None
    load: Any = None
    force: float | None = None
    unbalance: float | None = None
    base: float | None = None
    acceleration: bool = False
    direction: str = "both"
    with_harmonic_balance: bool = True
    strokes: int | None = None
    max_cycles: int | None = None
    criterion: Any = None
    progress: Callable | None = field(default=None, compare=False)
    name: ClassVar[str] = HARMONIC_SWEEP

    def __post_init__(self) -> None:
        from pdamper.coupling.frf import SWEEPS, HarmonicLoad

        given = {k: v for k, v in (("force", self.force), ("unbalance", self.unbalance),
                                   ("base", self.base)) if v is not None}
        if (self.load is None) == (not given) or len(given) > 1:
            raise InputError("load", "give one load: load=HarmonicLoad(...), force=, "
                             "unbalance= or base=")
        if self.load is None:
            ((kind, amplitude),) = given.items()
            object.__setattr__(self, "load", HarmonicLoad(kind, amplitude, self.acceleration))
        elif not isinstance(self.load, HarmonicLoad):
            raise InputError("load", f"must be a HarmonicLoad, got {type(self.load).__name__}")
        if self.direction not in (*SWEEPS, "none"):
            raise InputError("sweep", f"must be up, down, both or none, got {self.direction!r}")

    def prepare(self, strategy: Coupling, model: Any, structure: Any) -> Any:
        from pdamper.coupling.frf import sweep_strategy

        sweep_strategy(model)
        # the stepped sine checks the structure itself (the forced response runs every
        # structure as its modes)
        return structure

    def solve(self, strategy: Coupling, model: Any, structure: Any) -> Any:
        from pdamper.coupling.frf import DEFAULT_STROKES, default_frequencies, frequency_response

        f = self.frequencies
        if f is None:
            f = default_frequencies(structure, float(getattr(model, "bed_mass", 0.0)))
        return frequency_response(
            model, structure, self.load, f, sweep=self.direction,
            with_harmonic_balance=self.with_harmonic_balance,
            strokes=DEFAULT_STROKES if self.strokes is None else self.strokes,
            max_cycles=self.max_cycles, criterion=self.criterion, progress=self.progress)


def as_experiment(value: Any) -> Experiment:
    """``value`` as an :class:`Experiment`: an experiment as it is, a number as the
    :class:`Release` from that deflection [m], a load history (or a load with a
    ``history()``) as its :class:`Loading`."""
    from pdamper.coupling.loads import LoadHistory

    if isinstance(value, Experiment):
        return value
    if isinstance(value, int | float | np.floating | np.integer) and not isinstance(value, bool):
        return Release(float(value))
    if isinstance(value, LoadHistory) or callable(getattr(value, "history", None)):
        return Loading(value)
    raise InputError("experiment", "must be an experiment (Release, Loading, HarmonicSweep) "
                     f"or an initial displacement [m], got {type(value).__name__}")


def with_run(experiment: Release, duration: float, sample_rate: float) -> Release:
    """The release ``experiment`` over ``duration`` [s] at ``sample_rate`` [Hz]."""
    return replace(experiment, duration=duration, sample_rate=sample_rate)
