"""The coupling table: one strategy per Level III coupling, and what each answers.

A damper model names its coupling (:attr:`pdamper.models.base.DamperModel.coupling`); the
strategy of that name (:data:`COUPLINGS`) puts the model on a structure for each experiment
it answers (:mod:`pdamper.coupling.experiments`): a release (the free decay of Sect. 4.2), a
load history, a harmonic sweep. A strategy declares, per experiment, the structures it runs
on (:data:`SINGLE_DOF`, :data:`MODES`); a one-mode
:class:`~pdamper.structure.modal.ModalStructure` whose damper, output and release points
coincide is Eq. (23) and runs through its 1-DOF equivalent where a strategy has no N-mode
form. Every dispatch (:class:`~pdamper.coupling.simulation.Simulation`,
:func:`~pdamper.coupling.loads.run_load`, :func:`~pdamper.coupling.frf.frequency_response`)
goes through :func:`coupling_of`; nothing else branches on a coupling's name.

This module is the bottom of :mod:`pdamper.coupling`: it imports no strategy. The strategies
(:mod:`pdamper.coupling.strategies`) register themselves here when the package is imported,
so that the modules they use (the load histories, the forced response) can dispatch through
the table without importing them back.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from typing import Any, ClassVar

from pdamper.errors import InputError

#: Structure kinds a strategy declares: a :class:`~pdamper.structure.SingleDOFStructure`
#: (Eq. 23) and a :class:`~pdamper.structure.modal.ModalStructure` of N modes.
SINGLE_DOF, MODES = "single_dof", "modes"
#: The experiments (:mod:`pdamper.coupling.experiments`) by the name strategies declare them.
RELEASE, LOAD_HISTORY, HARMONIC_SWEEP = "release", "load_history", "harmonic_sweep"


class Coupling:
    """A Level III coupling strategy (its subclasses are the rows of :data:`COUPLINGS`).

    A strategy is stateless; its methods take the model and the structure. ``answers`` maps
    each experiment it runs to the structure kinds it runs on; a method of an experiment it
    does not answer is not called.

    Attributes
    ----------
    name
        The coupling's name, as the models give it (``DamperModel.coupling``).
    answers
        ``{experiment: (structure kinds)}``, e.g. ``{"release": ("single_dof", "modes")}``.
    harmonic_balance
        Whether the model's describing function is cheap enough for harmonic balance in a
        harmonic sweep (:func:`pdamper.coupling.frf.harmonic_balance`).
    structure_hint
        What to use instead where a structure is not answered (the end of the error).
    integrates_particles
        Whether the particles themselves are integrated with the structure (the DEM: a run
        costs what the DEM costs, :func:`pdamper.resources.dem_cost`), rather than a damper
        force from a model of the bed (a pseudo force, a plastic block).
    """

    name: ClassVar[str] = ""
    answers: ClassVar[dict[str, tuple[str, ...]]] = {}
    harmonic_balance: ClassVar[bool] = False
    structure_hint: ClassVar[str] = "use a pseudo-force model (analytic, fields) for N modes"
    integrates_particles: ClassVar[bool] = False

    # ------------------------------------------------------------------ the experiments
    def free_vibration(self, model, structure, duration: float, initial_displacement: float,
                       sample_rate: float = 2000.0):
        """Release of a 1-DOF ``structure`` from rest at ``initial_displacement`` [m] over
        ``duration`` [s]; a :class:`~pdamper.coupling.results.FreeVibrationResult`."""
        raise NotImplementedError

    def modal_free_vibration(self, model, structure, duration: float,
                             initial_displacement: float, sample_rate: float = 2000.0):
        """The release of an N-mode ``structure`` (same arguments and result)."""
        raise NotImplementedError

    def load(self, model, structure, load, sample_rate: float = 2000.0, tail: float = 0.0):
        """Response to a :class:`~pdamper.coupling.loads.LoadHistory` over the record plus
        ``tail`` [s]; a :class:`~pdamper.coupling.loads.LoadResponse`."""
        raise NotImplementedError

    def sweep_cost(self, structure, frequencies, sweeps: int, max_cycles, drivers):
        """What a harmonic sweep costs where the strategy judges its own stepped sine (a
        :class:`~pdamper.resources.Cost`, from the N-mode ``structure``, the ``frequencies``
        [Hz] array, the number of ``sweeps`` and the cap ``max_cycles`` or None); None where
        :func:`pdamper.runs.resources.frf_cost` judges it (a describing function, the DEM)."""
        return None

    def load_cost(self, model, structure, load, sample_rate: float, tail: float):
        """What :meth:`load` costs where it is more than seconds (a
        :class:`pdamper.resources.Cost`, judged before the run), else None."""
        return None

    def check_load_structure(self, model, structure) -> None:
        """Raise InputError if :meth:`load` cannot run on ``structure``."""
        self.structure_for(LOAD_HISTORY, model, structure)

    @property
    def checks_load_structure(self) -> bool:
        """Whether the strategy checks a load history's structure beyond the kinds it
        declares (its own :meth:`check_load_structure`)."""
        return type(self).check_load_structure is not Coupling.check_load_structure

    def stepped_sine(self, model, structure, load, frequency, direction: str, **options):
        """One stepped sine of a harmonic sweep (:mod:`pdamper.coupling.frf`): a
        :class:`~pdamper.coupling.frf.FRFCurve`."""
        raise NotImplementedError

    # ------------------------------------------------------------------ the table's checks
    def runs(self, experiment: str, structure: Any = None) -> bool:
        """Whether this strategy answers ``experiment`` (on ``structure``, if given, as it
        is: a one-mode structure it would run through its 1-DOF equivalent counts as no)."""
        kinds = self.answers.get(experiment, ())
        return bool(kinds) if structure is None else structure_kind(structure) in kinds

    def structure_for(self, experiment: str, model, structure):
        """The structure this strategy runs ``experiment`` on: ``structure`` itself, or the
        1-DOF equivalent of a one-mode structure whose damper, output and release points
        coincide (Eq. 23) where it has no N-mode form; InputError (field ``structure``)
        otherwise."""
        if self.runs(experiment, structure):
            return structure
        if structure_kind(structure) == MODES and SINGLE_DOF in self.answers.get(experiment, ()) \
                and structure.modes == 1 and structure.coincident:
            return structure.equivalent_single_dof()
        of = "its models" if model is None else type(model).__name__
        raise InputError("structure", f"the {self.name} coupling of {of} "
                         "needs a single-DOF structure (or one mode with the damper at the "
                         f"output and release point); {self.structure_hint}")

    def __call__(self, model, structure, duration: float, initial_displacement: float,
                 sample_rate: float = 2000.0):
        """The release (as the entries of :data:`COUPLINGS` were called): the free vibration
        of the structure's kind."""
        if structure_kind(structure) == MODES:
            return self.modal_free_vibration(model, structure, duration, initial_displacement,
                                             sample_rate)
        return self.free_vibration(model, structure, duration, initial_displacement,
                                   sample_rate)

    def __repr__(self) -> str:
        return f"<coupling {self.name}: {', '.join(self.answers)}>"


#: The coupling table: the strategy of each coupling name (a new coupling is one subclass of
#: :class:`Coupling`, registered with :func:`register`).
COUPLINGS: dict[str, Coupling] = {}


def register(*classes: type[Coupling]) -> None:
    """Put one strategy of each class in :data:`COUPLINGS` under its name."""
    for cls in classes:
        if not cls.name:
            raise ValueError(f"{cls.__name__} has no coupling name")
        COUPLINGS[cls.name] = cls()


def structure_kind(structure: Any) -> str:
    """:data:`MODES` for a :class:`~pdamper.structure.modal.ModalStructure`, else
    :data:`SINGLE_DOF`."""
    from pdamper.structure.modal import ModalStructure

    return MODES if isinstance(structure, ModalStructure) else SINGLE_DOF


def coupling_of(model: Any, experiment: str | None = None, field: str = "model",
                missing: Callable[[Any], str] | None = None) -> Coupling:
    """The strategy of ``model``'s coupling (answering ``experiment``, if given); an
    InputError naming ``field`` otherwise (its message ``missing(model)`` where given)."""
    name = getattr(model, "coupling", None)
    strategy = COUPLINGS.get(name) if isinstance(name, str) else None
    if strategy is None or (experiment is not None and not strategy.runs(experiment)):
        if missing is not None:
            raise InputError(field, missing(model))
        raise InputError(field, f"coupling {name!r} of {type(model).__name__} is not one of "
                         f"{', '.join(COUPLINGS)}")
    return strategy


def answering(experiment: str, structure_kind_: str | None = None) -> tuple[str, ...]:
    """Names of the couplings that answer ``experiment`` (on a structure kind, if given)."""
    return tuple(n for n, c in COUPLINGS.items()
                 if (structure_kind_ in c.answers.get(experiment, ()) if structure_kind_
                     else experiment in c.answers))


class CouplingView(Mapping):
    """A read-only view of :data:`COUPLINGS`: ``value(strategy)`` of each strategy for which
    ``when(strategy)`` holds, by name, as the table stands when it is read (the per-experiment
    tables of earlier versions, e.g. :data:`pdamper.coupling.loads.LOAD_COUPLINGS`)."""

    def __init__(self, value: Callable[[Coupling], Any], when: Callable[[Coupling], bool]):
        self._value, self._when = value, when

    def __getitem__(self, name: str) -> Any:
        strategy = COUPLINGS[name]
        if not self._when(strategy):
            raise KeyError(name)
        return self._value(strategy)

    def __iter__(self) -> Iterator[str]:
        return iter([n for n, c in COUPLINGS.items() if self._when(c)])

    def __len__(self) -> int:
        return sum(1 for c in COUPLINGS.values() if self._when(c))

    def __repr__(self) -> str:
        return f"CouplingView({dict(self)!r})"


def has_load_cost(strategy: Coupling) -> bool:
    """Whether ``strategy``'s load history has a cost judged before it runs
    (:meth:`Coupling.load_cost` overridden)."""
    return type(strategy).load_cost is not Coupling.load_cost
