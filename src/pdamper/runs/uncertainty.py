"""The propagation of a scenario's uncertain inputs to its answers (``--uncertainty N``).

The inputs given as ``"value +- sd"`` (:mod:`pdamper.io.uncertain`) are sampled
(:func:`pdamper.design.uncertainty.propagate`: Sobol' points, N (d + 2) + 1 runs for d
inputs) and every sample's answers computed: Level II at ``[excitation]``
(:func:`level2_answers`; the DEM: :func:`dem_answers`, in parallel on the sweep engine by
:func:`dem_batch`), the map of ``[map]`` (:func:`map_answers`) or the Level III free decay
(:func:`level3_answers`), the forced response of ``pdamper frf`` (:func:`frf_answers`) or
the response to a load history (:func:`load_answers`). :func:`check_cost` judges the
propagation's cost before any run; :func:`propagate_scenario` runs it.

The inputs the sampled fidelity does not use (its declared
:attr:`~pdamper.models.base.DamperModel.unused_inputs`, e.g. the friction in the analytical
bed) are still sampled, so that the design and its indices are those of every input given,
and are reported under ``not_used`` with the fidelities that do use them
(:func:`pdamper.models.registry.not_used`): their zero index says nothing of the damper,
only of the model asked.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from pdamper.errors import InputError
from pdamper.io.uncertain import sampled_damper, with_values

#: Sample rate of the Level III runs of a propagation [Hz]: the peaks are exact in the
#: pseudo-force coupling (as in the design study); the trajectory is not stored.
_SAMPLE_RATE = 200.0
LEVEL2_UNITS = {"loss_factor": "1", "effective_mass_ratio": "1", "effective_mass": "kg",
                "dissipated_energy_per_cycle": "J"}
LEVEL3_UNITS = {"amplitude_at": "m", "final_amplitude": "m", "mean_damping_ratio": "1",
                "envelope": "m"}
#: Times of the Level III envelope band (from release to the end of the run).
ENVELOPE_POINTS = 101
FRF_UNITS = {"peak": "m", "peak_frequency": "Hz", "rms": "m", "amplitude": "m"}
LOAD_UNITS = {"peak": "m", "rms": "m", "peak_acceleration": "m/s^2",
              "rms_acceleration": "m/s^2", "dissipated_energy": "J", "envelope": "m"}
#: Most and fewest windows of the load response's envelope band (the largest |x| in each;
#: each a period of the structure's first mode where that fits).
LOAD_WINDOWS = (20, 400)


def _load_windows(scenario, history, tail: float):
    """The edges [s] of the envelope's windows of a load response: about one period of
    the first natural frequency each (:data:`LOAD_WINDOWS`)."""
    import numpy as np

    end = history.duration + tail
    f1 = scenario.structure_model().natural_frequency
    n = int(np.clip(round(end * f1), *LOAD_WINDOWS))
    return np.linspace(0.0, end, n + 1)
#: One-core seconds of one Level II sample per fidelity: the sampled scenario and damper
#: built and the model's response at ``[excitation]`` (measured with the analytical model:
#: 1.7-2.2 ms per sample on the 2-core machine, rounded up; the effective fields'
#: interpolation is cheaper than building the sample, which dominates, so it is given the
#: same bound). A sample is far dearer than one point of an analytical map (0.5 ms), whose
#: scenario and damper are built once.
SECONDS_PER_LEVEL2_SAMPLE = {"analytic": 3e-3, "fields": 3e-3}


def _model_class(scenario, name: str | None):
    from pdamper.models import get_damper_model

    field = "model" if name is not None else "simulation.model"
    cls = get_damper_model(scenario.simulation.model if name is None else name, field)
    if cls.expensive:
        raise InputError("uncertainty", f"the {cls.fidelity} model is not sampled (N (inputs "
                         "+ 2) runs of seconds to hours each); use --model analytic or fields")
    return cls


def level2_answers(scenario, model: str | None = None):
    """``evaluate(values) -> answers`` at ``[excitation]``: loss factor, effective mass
    (ratio and kg), dissipated energy per cycle (:data:`LEVEL2_UNITS`)."""
    _model_class(scenario, model or "analytic")

    def evaluate(values: dict[str, float]) -> dict[str, float]:
        sc = with_values(scenario, values)
        d = sc.damper()
        r = sc.model(model or "analytic", d).response(sc.excitation.frequency,
                                                     sc.excitation.amplitude)
        return {"loss_factor": float(r.loss_factor),
                "effective_mass_ratio": float(r.effective_mass_ratio),
                "effective_mass": float(r.effective_mass),
                "dissipated_energy_per_cycle": float(r.dissipated_energy_per_cycle)}

    return evaluate


def level3_answers(scenario, model: str | None = None):
    """``evaluate(values) -> answers`` of the free decay of ``[simulation]``: amplitude
    envelope at ``[optimization] at``, final amplitude, mean damping ratio of the cycles
    that end by then (Eqs. 24-25; :data:`LEVEL3_UNITS`), and the envelope at
    :data:`ENVELOPE_POINTS` times from 0 to the duration (``envelope``: its band)."""
    from pdamper.coupling import Simulation
    from pdamper.design.study import make_objective

    _model_class(scenario, model)
    at, duration = scenario.optimization.at, scenario.simulation.duration
    if at > duration:
        raise InputError("optimization.at", f"the time of the amplitude ({at:g} s) must be "
                         f"within the simulated {duration:g} s (simulation.duration)")

    import numpy as np

    times = np.linspace(0.0, duration, ENVELOPE_POINTS)

    def evaluate(values: dict[str, float]) -> dict:
        sc = with_values(scenario, values)
        structure = sc.structure_model()
        x0 = sc.structure.initial_displacement
        res = Simulation(structure, sc.model(model, sc.damper()), x0).run(duration,
                                                                           _SAMPLE_RATE)
        zeta, _ = make_objective("mean-damping", at, x0, structure).evaluate(res)
        return {"amplitude_at": float(res.amplitude_at(at)),
                "final_amplitude": float(res.final_amplitude), "mean_damping_ratio": zeta,
                "envelope": np.array([res.amplitude_at(t) for t in times])}

    return evaluate


def map_answers(scenario, model: str = "analytic"):
    """``evaluate(values) -> answers`` of the Level II map of ``[map]``: the largest and
    the mean loss factor over the grid (scalars), and the loss factor and effective mass
    ratio of every cell (arrays: their bands, :data:`MAP_BANDS`)."""
    _model_class(scenario, model)
    f, x = scenario.map_grid()
    counts = scenario.map_particles()

    def evaluate(values: dict[str, float]) -> dict:
        import numpy as np

        from pdamper.analysis.fields import effective_field

        sc = with_values(scenario, values)
        ds = effective_field(sc.map_model(model, sc.damper()), f, x, particles=counts)
        eta = np.asarray(ds["loss_factor"].values, float)
        return {"max_loss_factor": float(np.nanmax(eta)),
                "mean_loss_factor": float(np.nanmean(eta)), "loss_factor": eta,
                "effective_mass_ratio": np.asarray(ds["effective_mass_ratio"].values, float)}

    return evaluate


def dem_answers(scenario):
    """``evaluate(values) -> answers`` of one DEM run at ``[excitation]`` (Level II): loss
    factor, effective mass ratio and kg, dissipated energy per cycle
    (:data:`LEVEL2_UNITS`). Every sample runs from the scenario's seed (the same packing):
    the spread is the inputs', not the packing's (``--realisations`` gives that)."""

    def evaluate(values: dict[str, float]) -> dict[str, float]:
        sc = with_values(scenario, values)
        r = sc.model("dem", sampled_damper(scenario, values)).response(
            sc.excitation.frequency, sc.excitation.amplitude)
        return {"loss_factor": float(r.loss_factor),
                "effective_mass_ratio": float(r.effective_mass_ratio),
                "effective_mass": float(r.effective_mass),
                "dissipated_energy_per_cycle": float(r.dissipated_energy_per_cycle)}

    return evaluate


def dem_point(params: dict, *, scenario) -> dict:
    """One sample of :func:`dem_answers` on a sweep worker (``params``: the sample)."""
    return dem_answers(scenario)(params)


def dem_batch(scenario, *, workers: int | None = None, serial: bool = False, progress=None):
    """``batch(points) -> answers`` of :func:`dem_answers` on the sweep engine
    (:func:`pdamper.sweep.run_sweep`: a local cluster of ``workers`` processes, default
    every core, or ``serial`` in this process): the DEM runs of a propagation in
    parallel (:func:`pdamper.design.uncertainty.propagate`'s ``batch``)."""
    import functools

    def batch(points: list[dict]) -> list[dict]:
        from pdamper.sweep import run_sweep

        res = run_sweep(functools.partial(dem_point, scenario=scenario), points, retries=0,
                        workers=workers, serial=serial,
                        progress=None if progress is None else
                        (lambda done, total, _p: progress(done, total)))
        bad = [p for p in res.points if not p.ok]
        if bad:
            shown = ", ".join(f"{k} = {v:.6g}" for k, v in bad[0].params.items())
            raise InputError("uncertainty", f"the DEM run of the sample {shown} failed: "
                             f"{bad[0].error}")
        return [p.values for p in res.points]

    return batch


def _sampled(scenario, values: dict[str, float], model: str | None):
    """The scenario's model (fidelity ``model``, default ``[simulation] model``) and
    structure at the sample ``values``."""
    sc = with_values(scenario, values)
    return sc.model(model, sampled_damper(scenario, values)), sc.structure_model()


def frf_answers(scenario, load, frequency, model: str | None = None):
    """``evaluate(values) -> answers`` of the forced response under the harmonic ``load``
    (:class:`~pdamper.coupling.frf.HarmonicLoad`) at ``frequency`` [Hz]: harmonic balance
    (every sample's describing functions; the stepped sines run at the nominal inputs
    alone), the largest stable (else edge, else any) amplitude of the output point at each
    frequency
    (``amplitude``: its band), its largest value over the frequencies (``peak``), where
    (``peak_frequency``) and its RMS over them (``rms``; :data:`FRF_UNITS`)."""
    import numpy as np

    from pdamper.coupling.frf import EDGE, HARMONIC_BALANCE, frequency_response

    cls = _model_class(scenario, model or scenario.simulation.model)
    if cls.coupling not in HARMONIC_BALANCE:  # pragma: no cover - every cheap model has one
        raise InputError("uncertainty", f"the {cls.fidelity} model has no harmonic balance "
                         "to sample")
    f = np.unique(np.atleast_1d(np.asarray(frequency, float)))

    def evaluate(values: dict[str, float]) -> dict:
        m, structure = _sampled(scenario, values, model)
        hb = frequency_response(m, structure, load, f, sweep="none").harmonic_balance
        assert hb is not None  # the pseudo-force coupling solves it
        # the stable solutions, and an edge (the response held at a jump of the damper's
        # describing function) where a frequency has no stable one; a frequency with
        # neither keeps its largest solution rather than counting as at rest
        held = hb.steady | (hb.branch == EDGE)
        a = np.where(held, hb.amplitude, np.nan)
        none = np.isnan(a).all(axis=1, keepdims=True)
        a = np.where(none, hb.amplitude, a)
        amp = np.nanmax(np.where(np.isnan(a).all(axis=1, keepdims=True), 0.0, a), axis=1)
        k = int(np.argmax(amp))
        return {"peak": float(amp[k]), "peak_frequency": float(f[k]),
                "rms": float(np.sqrt(np.mean(amp**2))), "amplitude": amp}

    return evaluate


def load_answers(scenario, history, tail: float, model: str | None = None):
    """``evaluate(values) -> answers`` of the response to the load ``history``
    (:class:`~pdamper.coupling.loads.LoadHistory`) plus ``tail`` [s]: peak and RMS of the
    output point's displacement and acceleration, the energy the damper dissipated, and the
    envelope (the largest |x| in each window, about a period of the first mode,
    :data:`LOAD_WINDOWS`: its band;
    :data:`LOAD_UNITS`)."""
    import numpy as np

    from pdamper.coupling.loads import check_model, run_load

    _model_class(scenario, model or scenario.simulation.model)
    rate = scenario.simulation.sample_rate
    edges = _load_windows(scenario, history, tail)

    def evaluate(values: dict[str, float]) -> dict:
        m, structure = _sampled(scenario, values, model)
        check_model(m, structure)
        r = run_load(m, structure, history, rate, tail)
        idx = np.clip(np.searchsorted(r.time - r.time[0], edges), 0, r.time.size - 1)
        x = np.abs(r.displacement)
        env = np.array([x[i:max(j, i + 1)].max() for i, j in zip(idx[:-1], idx[1:],
                                                                   strict=True)])
        return {"peak": r.peak, "rms": r.rms, "peak_acceleration": r.peak_acceleration,
                "rms_acceleration": r.rms_acceleration,
                "dissipated_energy": float(r.dissipated_energy), "envelope": env}

    return evaluate


# --------------------------------------------------------------------------- design studies
def parse_quantile(value, field: str = "robust_quantile") -> float:
    """``--robust-quantile`` as a number in (0, 1) (``0.9``, ``"90%"``)."""
    from pdamper.units import parse_quantity

    q = value if isinstance(value, float) else parse_quantity(str(value), "", field)
    if not 0.0 < q < 1.0:
        raise InputError(field, f"must be in (0, 1) (0.9: the design whose objective 90 % "
                         f"of the uncertain inputs' samples meet), got {value!r}")
    return float(q)


@dataclass
class UncertainDesignEvaluator:
    """A design study's objective under the uncertain inputs: each design evaluated at
    the ``2 n`` quasi-Monte Carlo samples of the inputs (the matrices A and B of
    :func:`pdamper.design.uncertainty.design_matrices`); its value is their mean, or with
    ``quantile`` q the robust value: the q-quantile of a minimised objective (the value
    that a fraction q of the samples meet), the (1 - q)-quantile of a maximised one. The
    candidate's extras hold ``objective_mean``, ``objective_std`` (divisor 2 n - 1),
    ``objective_nominal`` (the nominal inputs), ``objective_p5`` ... ``objective_p95`` and
    ``objective_quantile``. Picklable for dask."""

    nominal: Any
    samples: list
    sense: str
    quantile: float | None = None

    def __call__(self, design: dict) -> tuple[float, dict]:
        import numpy as np

        from pdamper.design.uncertainty import PERCENTILES

        value0, extras = self.nominal(design)
        v = np.array([e(design)[0] for e in self.samples], float)
        if not np.all(np.isfinite(v)):
            raise InputError("uncertainty", "the objective is not finite at some samples of "
                             "the uncertain inputs; narrow their standard deviations")
        q = None
        if self.quantile is not None:
            q = float(np.quantile(v, self.quantile if self.sense == "min"
                                  else 1.0 - self.quantile))
        out = {**extras, "objective_nominal": float(value0), "objective_mean": float(v.mean()),
               "objective_std": float(v.std(ddof=1)),
               **{f"objective_p{p:g}": float(x)
                  for p, x in zip(PERCENTILES, np.percentile(v, PERCENTILES), strict=True)}}
        if q is not None:
            out["objective_quantile"] = q
        return (float(v.mean()) if q is None else q), out

    def check(self, design: dict) -> None:
        """The physical limits of the design at the nominal inputs."""
        self.nominal.check(design)


def design_evaluator(scenario, n: int, seed: int, objective, quantile: float | None = None):
    """The :class:`UncertainDesignEvaluator` of the scenario's design study for
    ``objective`` (:func:`pdamper.design.study.make_objective`) at ``2 n`` samples of its
    uncertain inputs (``n`` base points, seeded)."""
    import functools

    from pdamper.design.study import DesignEvaluator
    from pdamper.design.uncertainty import check_points, design_matrices

    check_points(n)
    inputs = scenario.uncertain_inputs()
    a, b = design_matrices(inputs, n, seed)
    x0 = scenario.structure.initial_displacement

    def at(values: dict[str, float]):
        sc = with_values(scenario, values)
        try:
            return DesignEvaluator(sc.structure_model(), sampled_damper(scenario, values), x0,
                                   objective, functools.partial(sc.model, None))
        except InputError as exc:
            shown = ", ".join(f"{k} = {v:.6g}" for k, v in values.items())
            raise InputError(exc.field, f"at the uncertainty sample {shown}: "
                             f"{exc.message}") from None

    samples = [at({u.field: float(m[i, j]) for i, u in enumerate(inputs)})
               for m in (a, b) for j in range(n)]
    return UncertainDesignEvaluator(at({u.field: u.value for u in inputs}), samples,
                                    objective.sense, quantile)


def check_design_cost(scenario, n: int, force: bool = False) -> None:
    """Refuse a design study whose every design runs ``2 n + 1`` times (the samples and
    the nominal) beyond the limits: the study's cost check
    (:func:`pdamper.runs.resources.check_resources`) with its time ``2 n + 1`` times over.

    A design's ``2 n + 1`` runs are one task (:class:`UncertainDesignEvaluator`, one after
    another), so the longest run is ``2 n + 1`` times one design's; a study evaluated in
    this process (:func:`study_in_process`: the designs one after another) is one run, its
    whole time judged against one run's limit (:data:`pdamper.resources.TIME_LIMIT`), not
    a sweep's."""
    from pdamper import resources
    from pdamper.runs.resources import check_resources

    runs = 2 * n + 1
    serial = study_in_process(scenario)

    def require(cost, force_=False):
        if cost.seconds > 0:
            one = cost.longest if cost.longest is not None else cost.seconds
            cost = resources.Cost(
                f"{cost.what} under the uncertain inputs", cost.seconds * runs, cost.memory,
                f"{runs} runs of every design ({n} Sobol' base points), each {cost.detail}",
                (*cost.drivers, ("uncertainty", n / 16)),
                runs=1 if serial else runs * max(cost.runs or 1, 1),
                longest=None if serial else one * runs,
                remedy="give --uncertainty fewer base points or vary fewer designs")
        return resources.require(cost, force_)

    check_resources(scenario, "optimization", None, force, require=require)


def study_in_process(scenario) -> bool:
    """Whether the scenario's design study evaluates its designs in this process, one
    after another (no scheduler, ``workers`` 0, or ``"auto"`` for a model that is not
    expensive or without dask.distributed), as ``pdamper optimize`` chooses."""
    import importlib.util

    from pdamper.models import get_damper_model

    o = scenario.optimization
    if o.scheduler is not None:
        return False
    if o.workers != "auto":
        return not o.workers
    cls = get_damper_model(scenario.simulation.model, "simulation.model")
    return not (cls.expensive and importlib.util.find_spec("distributed") is not None)


#: The map's answers whose bands become variables of its NetCDF file.
MAP_BANDS = ("loss_factor", "effective_mass_ratio")
MAP_UNITS = {"max_loss_factor": "1", "mean_loss_factor": "1", "loss_factor": "1",
             "effective_mass_ratio": "1"}


def check_cost(scenario, level: str, n: int, force: bool = False,
               model: str | None = None, *, frequencies: int = 1, history=None,
               tail: float = 0.0) -> None:
    """Refuse a propagation whose ``n (d + 2) + 1`` runs exceed the limits of
    :mod:`pdamper.resources`, before any run (``frequencies``: of a forced response,
    ``"frf"``; ``history`` and ``tail``: of a load history, ``"load"``).

    The samples of ``"level2"`` (fidelity ``model``, default analytic;
    :data:`SECONDS_PER_LEVEL2_SAMPLE`), ``"map"`` and ``"level3"`` run one after another in
    this process: their sum is one run's time (:data:`pdamper.resources.TIME_LIMIT`); the
    DEM's run in parallel on the sweep engine, each judged as one run of a sweep.
    """
    from pdamper import resources

    d = len(scenario.uncertain_inputs())
    runs = n * (d + 2) + 1
    if level == "map":
        (_, _, nf), (_, _, nx) = scenario.map_ranges()
        counts = scenario.map_particles()
        one = resources.analytic_map_cost(float(nf) * nx * (1 if counts is None
                                                            else counts.size))
    elif level == "dem":  # N (d + 2) + 1 DEM runs at the excitation, one after another
        from pdamper.runs.resources import excitation_cost

        dem = excitation_cost(scenario, "dem")
        assert dem is not None  # the DEM states what a run costs
        one = dem
    elif level == "frf":  # a describing-function table per frequency, then the solution
        from pdamper.runs.resources import frf_sample_cost

        one = frf_sample_cost(scenario, frequencies)
    elif level == "load":  # one pseudo-force run over the record and its tail
        one = resources.pseudo_force_cost(history.duration + tail,
                                          scenario.simulation.sample_rate,
                                          scenario.structure_model().natural_frequency)
    elif level == "level3":
        one = resources.pseudo_force_cost(scenario.simulation.duration, _SAMPLE_RATE,
                                          scenario.structure_model().natural_frequency)
    else:
        fidelity = _model_class(scenario, model or "analytic").fidelity
        seconds = SECONDS_PER_LEVEL2_SAMPLE.get(fidelity,
                                                max(SECONDS_PER_LEVEL2_SAMPLE.values()))
        one = resources.Cost(f"the {fidelity} sample", seconds,
                             resources.ANALYTIC_BYTES_PER_POINT,
                             f"one {fidelity} response at the excitation", ())
    serial = level != "dem"  # one process, one sample after the other: one run's time
    resources.require(resources.Cost(
        "the uncertainty propagation", one.seconds * runs, one.memory,
        f"{runs} runs, each {one.detail}", (("uncertainty", n / 64),),
        runs=1 if serial else runs, longest=None if serial else one.seconds), force)


def propagate_scenario(scenario, level: str, n: int, seed: int = 0, model: str | None = None,
                       progress=None, batch=None, *, load=None, frequency=None,
                       history=None, tail: float = 0.0):
    """Propagate the scenario's uncertain inputs to its ``"level2"``, ``"map"``,
    ``"level3"``, ``"frf"`` (``load``, ``frequency``) or ``"load"`` (``history``,
    ``tail``) answers with ``n`` base points
    (:func:`pdamper.design.uncertainty.propagate`). A sample the models refuse is an error
    naming its field and the sample; the inputs the sampled fidelity does not use are
    listed in the result's ``not_used`` (module docstring)."""
    import dataclasses

    from pdamper.design.uncertainty import check_points, propagate
    from pdamper.models import get_damper_model
    from pdamper.models.registry import not_used

    check_points(n)
    inputs = scenario.uncertain_inputs()
    fidelity = {"dem": "dem"}.get(level) or model or (
        "analytic" if level in ("level2", "map") else scenario.simulation.model)
    unused = not_used(get_damper_model(fidelity, "model"), [u.field for u in inputs])
    if level == "frf":
        evaluate, units = frf_answers(scenario, load, frequency, model), FRF_UNITS
    elif level == "load":
        evaluate, units = load_answers(scenario, history, tail, model), LOAD_UNITS
    elif level == "level2":
        evaluate, units = level2_answers(scenario, model), LEVEL2_UNITS
    elif level == "map":
        evaluate, units = map_answers(scenario, model or "analytic"), MAP_UNITS
    elif level == "dem":
        evaluate, units = dem_answers(scenario), LEVEL2_UNITS
    else:
        evaluate, units = level3_answers(scenario, model), LEVEL3_UNITS

    def checked(values):
        try:
            return evaluate(values)
        except InputError as exc:
            shown = ", ".join(f"{k} = {v:.6g}" for k, v in values.items())
            hint = " (narrow the standard deviations)" if exc.field in values else ""
            raise InputError(exc.field, f"at the uncertainty sample {shown}: "
                             f"{exc.message}{hint}") from None

    result = propagate(checked, inputs, n, seed, units=units, progress=progress, batch=batch)
    if "envelope" in result.bands:  # its times: release to the end of the run [s]
        import numpy as np

        if level == "load":  # the windows' centres [s]
            edges = _load_windows(scenario, history, tail)
            result.bands["envelope"]["time"] = 0.5 * (edges[:-1] + edges[1:])
        else:
            result.bands["envelope"]["time"] = np.linspace(
                0.0, scenario.simulation.duration, ENVELOPE_POINTS)
    if "amplitude" in result.bands:  # the forced response's frequencies [Hz]
        import numpy as np

        result.bands["amplitude"]["frequency"] = np.unique(
            np.atleast_1d(np.asarray(frequency, float)))
    return dataclasses.replace(result, not_used=unused)


__all__ = ["ENVELOPE_POINTS", "FRF_UNITS", "LEVEL2_UNITS", "LEVEL3_UNITS", "LOAD_UNITS",
           "LOAD_WINDOWS", "MAP_BANDS", "MAP_UNITS", "UncertainDesignEvaluator", "check_cost",
           "check_design_cost", "dem_answers", "dem_batch", "design_evaluator",
           "dem_point", "frf_answers", "level2_answers", "level3_answers", "load_answers",
           "map_answers", "parse_quantile", "propagate_scenario", "study_in_process"]
