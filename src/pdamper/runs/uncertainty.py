"""The propagation of a scenario's uncertain inputs to its answers (``--uncertainty N``).

The inputs given as ``"value +- sd"`` (:mod:`pdamper.io.uncertain`) are sampled
(:func:`pdamper.design.uncertainty.propagate`: Sobol' points, N (d + 2) + 1 runs for d
inputs) and every sample's answers computed: Level II at ``[excitation]``
(:func:`level2_answers`; the DEM: :func:`dem_answers`, in parallel on the sweep engine by
:func:`dem_batch`), the map of ``[map]`` (:func:`map_answers`) or the Level III free decay
(:func:`level3_answers`). :func:`check_cost` judges the propagation's cost before any run;
:func:`propagate_scenario` runs it.
"""

from __future__ import annotations

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


#: The map's answers whose bands become variables of its NetCDF file.
MAP_BANDS = ("loss_factor", "effective_mass_ratio")
MAP_UNITS = {"max_loss_factor": "1", "mean_loss_factor": "1", "loss_factor": "1",
             "effective_mass_ratio": "1"}


def check_cost(scenario, level: str, n: int, force: bool = False,
               model: str | None = None) -> None:
    """Refuse a propagation whose ``n (d + 2) + 1`` runs exceed the limits of
    :mod:`pdamper.resources`, before any run.

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
    elif level == "level3":
        one = resources.pseudo_force_cost(scenario.simulation.duration, _SAMPLE_RATE,
                                          scenario.structure_model().natural_frequency)
    else:
        fidelity = _model_class(scenario, model or "analytic").fidelity
        seconds = SECONDS_PER_LEVEL2_SAMPLE.get(fidelity, max(SECONDS_PER_LEVEL2_SAMPLE.values()))
        one = resources.Cost(f"the {fidelity} sample", seconds, resources.ANALYTIC_BYTES_PER_POINT,
                             f"one {fidelity} response at the excitation")
    serial = level != "dem"  # one process, one sample after the other: one run's time
    resources.require(resources.Cost(
        "the uncertainty propagation", one.seconds * runs, one.memory,
        f"{runs} runs, each {one.detail}", (("uncertainty", n / 64),),
        runs=1 if serial else runs, longest=None if serial else one.seconds), force)


def propagate_scenario(scenario, level: str, n: int, seed: int = 0, model: str | None = None,
                       progress=None, batch=None):
    """Propagate the scenario's uncertain inputs to its ``"level2"``, ``"map"`` or
    ``"level3"`` answers with ``n`` base points (:func:`pdamper.design.uncertainty.propagate`). A
    sample the models refuse is an error naming its field and the sample."""
    from pdamper.design.uncertainty import check_points, propagate

    check_points(n)
    inputs = scenario.uncertain_inputs()
    if level == "level2":
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

        result.bands["envelope"]["time"] = np.linspace(0.0, scenario.simulation.duration,
                                                       ENVELOPE_POINTS)
    return result


__all__ = ["ENVELOPE_POINTS", "LEVEL2_UNITS", "LEVEL3_UNITS", "MAP_BANDS", "MAP_UNITS",
           "check_cost", "dem_answers", "dem_batch", "dem_point", "level2_answers",
           "level3_answers", "map_answers", "propagate_scenario"]
