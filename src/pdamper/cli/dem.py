"""``pdamper dem``: a DEM run of a damper under harmonic excitation (Level II).

Example::

    pdamper dem --frequency 10Hz --amplitude 32mm --particles 32 --cycles 8 --out run.nc

prints a summary (``--json``: ``loss_factor``, ``effective_mass_ratio``,
``energy_balance_error`` and more, with the inputs, the pdamper version and the seed; the
run's own keys are those of :meth:`pdamper.dem.DEMResult.summary`: ``steps`` and
``wall_seconds`` of the whole run, settling included (as in a map's diagnostics),
``excitation_steps`` and ``excitation_wall_seconds`` of the excitation, ``settle_steps``
and ``settle_seconds`` of the settling before it). Every run option
can also come from the scenario's ``[dem]`` section; the command line overrides the file.
``--realisations N`` runs N random packings (seeds ``--seed`` + 0..N-1) on the sweep
engine (``--workers``, ``--serial``): the loss factor and effective mass ratio are then
their means, the spread under ``realisations``
(:mod:`pdamper.runs.realisations`).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, cast

import typer

from pdamper.cli import _uncertainty
from pdamper.cli._common import (
    ForceOpt,
    JsonOpt,
    ScenarioOpt,
    check_output,
    check_output_directory,
    emit,
    load,
    metadata,
    with_flags,
)

if TYPE_CHECKING:  # pragma: no cover
    from pdamper.dem.result import DEMResult
    from pdamper.io.scenario import Scenario
    from pdamper.models.base import DamperResponse
    from pdamper.models.dem import DEMDamper

#: The options of ``pdamper dem`` that set a scenario key, one row each: ``(flag, key,
#: type, help)``. The key's declaration (:mod:`pdamper.models.settings`,
#: :mod:`pdamper.dem.settings` for ``dem.*``) holds its unit, range and default; a new DEM
#: option is one declared setting and one row here. Flags whose name differs from the
#: setting's (``--free-flight``: ``gear_free_flight``) are the public names.
FLAGS: tuple[tuple[str, str, type, str], ...] = (
    ("--frequency", "excitation.frequency", str, "Excitation frequency f, e.g. '10Hz'."),
    ("--amplitude", "excitation.amplitude", str, "Excitation amplitude X, e.g. '32mm'."),
    ("--particles", "particles.count", int, "Number of spheres (benchmark box: <= 192)."),
    ("--cycles", "dem.cycles", str, "'auto' (until the loss factor is steady, default) or a "
     "number of excitation cycles (the paper: 8)."),
    ("--max-cycles", "dem.max_cycles", int, "Upper bound of a run until steady."),
    ("--integrator", "dem.integrator", str, "gear (variable step, default), verlet, or auto "
     "(gear, handing over to verlet where gear's steps are held by its stability limit: "
     "jammed beds)."),
    ("--skip-cycles", "dem.skip_cycles", int, "Cycles left out of the complex power."),
    ("--friction", "particles.friction", float, "Friction coefficient mu, all contacts."),
    ("--restitution-pp", "dem.restitution_pp", float, "Constant sphere-sphere COR."),
    ("--restitution-pw", "dem.restitution_pw", float, "Constant sphere-wall COR."),
    ("--damping-model", "dem.damping_model", str, "exact (default), gonthier (the paper's) "
     "or tsuji (LIGGGHTS/EDEM 'Hertz with COR')."),
    ("--seed", "dem.seed", int, "Seed of the random packing (recorded always)."),
    ("--packing", "dem.packing", str, "lattice (the paper's 4x4 layers), random, or auto "
     "(random where every sphere fits at random, else lattice)."),
    ("--sample-rate", "dem.sample_rate", str, "Sampling rate of the time series, e.g. "
     "'4 kHz'."),
    ("--safety", "dem.safety", float, "Time step / Hertz contact time."),
    ("--error-estimate/--no-error-estimate", "dem.error_estimate", bool, "Estimate the "
     "integration error of the loss factor and effective mass from a refined companion run "
     "(about twice the cost); redo refined if it misses --accuracy."),
    ("--accuracy", "dem.accuracy", float, "Target of the error estimate, relative (default "
     "0.01)."),
    ("--free-flight/--no-free-flight", "dem.gear_free_flight", bool, "Gear steps only the "
     "spheres that may touch something, the others fly their exact parabola (default on; "
     "off: every sphere at every step)."),
    ("--snapshot-rate", "dem.snapshot_rate", str, "Snapshots per second for --vtk."),
    ("--gravity", "excitation.gravity", str, "g, e.g. '9.81 m/s^2' (default); '0 m/s^2' for "
     "a structure in orbit."),
    ("--friction-model", "dem.friction_model", str, "regularised (the paper's tanh law, "
     "default) or spring (tangential spring with Coulomb limit, LIGGGHTS' 'tangential "
     "history'; needs --integrator verlet or auto)."),
)


@with_flags(FLAGS)
def dem(
    flags: dict,
    out: Annotated[str | None, typer.Option("--out",
                   help="NetCDF file for the time series.")] = None,
    vtk: Annotated[str | None, typer.Option("--vtk",
                   help="Directory for ParaView snapshots (.vtp + .pvd); its parent must "
                   "exist.")] = None,
    realisations: Annotated[str | None, typer.Option(
        "--realisations",
        help="Independent random packings (seeds --seed, --seed + 1, ...) run in parallel; "
             "the loss factor and effective mass ratio become their mean, with the spread "
             "under 'realisations' (default 1: one run).")] = None,
    workers: Annotated[int | None, typer.Option(
        help="Worker processes of the local cluster for --realisations and --uncertainty "
             "(default: every core).")] = None,
    serial: Annotated[bool, typer.Option(
        "--serial", help="Run the realisations (or the --uncertainty samples) in this "
                         "process, without dask.")] = False,
    uncertainty: _uncertainty.UncertaintyOpt = None,
    uncertain: _uncertainty.UncertainOpt = None,
    uncertainty_seed: _uncertainty.UncertaintySeedOpt = 0,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Run the DEM of a damper (default: the paper's benchmark) under harmonic excitation
    and apply the complex power method (Eqs. 1-4). Options left out take the scenario's
    values (`pdamper example-scenario` shows every default)."""
    from pdamper.errors import InputError

    _check_cycles(flags)
    from pdamper.models.dem import reset_settling_claims

    reset_settling_claims()  # the command's output as in a process of its own
    sc = load(scenario, runs=("excitation",), model="dem", force=force,
              **_uncertainty.merged({key.replace(".", "__"): value
                                     for key, value in flags.items()}, uncertain,
                                    allow_fits=True))
    fitted = _uncertainty.fits(uncertain)
    if fitted:  # the fitted COR curves become uncertain inputs (their principal axes)
        from pdamper.io.uncertain import add_fit_inputs

        add_fit_inputs(sc, fitted)
    n_real = _realisation_count(realisations, sc, force)
    if workers is not None and workers < 1:
        raise InputError("workers", f"must be a whole number >= 1, got {workers}")
    if uncertainty is not None:
        for name, value in (("realisations", n_real > 1 or None), ("out", out),
                            ("vtk", vtk)):
            if value is not None:
                raise InputError("uncertainty", f"cannot be combined with --{name} (the "
                                 "samples run from one packing and keep no time series)")
        _uncertainty.check(sc, "dem", uncertainty, force)
        return _uncertainty_run(sc, uncertainty, uncertainty_seed, as_json, workers=workers,
                                serial=serial)
    if n_real > 1:
        for name, value in (("out", out), ("vtk", vtk)):
            if value is not None:
                raise InputError("realisations", f"must be 1 with --{name} (the time series "
                                 f"and snapshots are of one run), got {n_real}")
        return _realisations(sc, n_real, workers=workers, serial=serial, force=force,
                             as_json=as_json)
    target = check_output(out)
    vtk_dir = check_output_directory(vtk, "vtk")
    if vtk is not None and sc.dem.snapshot_rate is None:  # option > scenario > VTK default
        from pdamper.dem.vtk import DEFAULT_SNAPSHOT_RATE

        sc = sc.model_copy(update={"dem": sc.dem.model_copy(
            update={"snapshot_rate": DEFAULT_SNAPSHOT_RATE})})
    damper = sc.damper()
    if damper.count < 1:
        raise InputError("particles.count", f"must be in [1, {damper.max_count}] for the DEM, "
                         f"got {damper.count}")
    model = cast("DEMDamper", sc.model("dem", damper))
    r = model.response(sc.excitation.frequency, sc.excitation.amplitude)
    from pdamper.runs.realisations import run_summary

    meta = metadata(sc, seed=model.seed)
    summary = run_summary(model, r)
    accuracy = {k: summary.pop(k) for k in ACCURACY_KEYS if k in summary}
    payload = {**summary, "units": UNITS, **meta, **accuracy}
    _write_outputs(r.details.item(), payload, meta, out, target, vtk_dir)
    emit(payload, as_json, _human_summary(sc, damper.count, model, r, payload))


def _check_cycles(flags: dict) -> None:
    """``--cycles``: 'auto' or a whole number (then set as one in ``flags``)."""
    from pdamper.errors import InputError

    cycles = flags["dem.cycles"]
    if cycles is not None and cycles != "auto":
        try:
            flags["dem.cycles"] = int(cycles)
        except ValueError:
            raise InputError("dem.cycles", f"must be 'auto' or a whole number >= 1, "
                             f"got {cycles!r}") from None


def _realisation_count(realisations: str | None, sc: Scenario, force: bool) -> int:
    """The number of ``--realisations`` (1 if not given), checked against the scenario."""
    if realisations is None:
        return 1
    from pdamper.errors import InputError
    from pdamper.runs.realisations import check_realisations

    try:
        n_real = int(realisations)
    except ValueError:
        raise InputError("realisations", f"must be a whole number >= 1, "
                         f"got {realisations!r}") from None
    return check_realisations(n_real, sc, force=force)


def _write_outputs(res: DEMResult, payload: dict, meta: dict, out: str | None,
                   target: Path | None, vtk_dir: Path | None) -> None:
    """The time series (``--out``) and the snapshots (``--vtk``) of the run ``res``, their
    paths added to ``payload``."""
    import json

    from pdamper.files import atomic_directory

    attrs = {"inputs": json.dumps(meta["inputs"]), "pdamper_version": meta["version"]}
    if target is not None and out is not None:
        res.write_netcdf(target, attrs=attrs)
        payload["out"] = str(Path(out))
    if vtk_dir is not None:
        with atomic_directory(vtk_dir, "vtk") as stage:
            pvd = res.write_vtk(stage)
        payload["vtk"] = str(vtk_dir / pvd.name)


def _human_summary(sc: Scenario, count: int, model: DEMDamper, r: DamperResponse,
                   payload: dict) -> str:
    """The summary ``pdamper dem`` prints without ``--json`` (``count`` spheres)."""
    f, x = sc.excitation.frequency, sc.excitation.amplitude
    st = r.diagnostics["stationarity"].item()
    motion = r.diagnostics["motion"].item()
    res = r.details.item()
    accuracy_line = ""
    if model.error_estimate:
        accuracy_line = (
            f"  integration error (estimate) eta +- {payload['loss_factor_error']:.2g}, "
            f"m_eff/m_bed +- {payload['effective_mass_ratio_error']:.2g}: "
            + ("within" if payload["accuracy_met"] else "NOT within")
            + f" {100 * model.accuracy.accuracy:g} % ({payload['accuracy_refinements']} refinements)\n"
            f"  realisation spread (1e-9 m)  eta +- "
            f"{payload['realisation_loss_factor_spread']:.2g}, m_eff/m_bed +- "
            f"{payload['realisation_effective_mass_ratio_spread']:.2g}"
            + (": the state depends on the transient or the realisation\n"
               if payload["realisation_dependent"] else "\n"))
    return (
        f"DEM ({model.integrator}, from the {payload['protocol']['start']}), "
        f"{count} spheres, f = {f:g} Hz, X = {x * 1e3:g} mm, "
        f"{st.cycles} cycles (complex power over cycles {st.first_cycle}-{st.last_cycle}, "
        + (("steady, a quiet bed)\n" if st.quiet else "steady)\n") if st.stationary
           else f"NOT steady: {st.reason})\n")
        + f"  effective loss factor        {float(r.loss_factor):.4g} +- {st.stderr:.2g}\n"
        f"  motion mode                  {motion.mode.title} ({motion.reason})\n"
        f"  effective mass ratio         {float(r.effective_mass_ratio):.4g}\n"
        f"  dissipated energy per cycle  {float(r.dissipated_energy_per_cycle) * 1e3:.4g} mJ\n"
        + accuracy_line
        + f"  energy ledger closes to      {res.energy_balance_error():.2e}\n"
        f"  largest overlap / radius     {res.max_overlap_ratio:.3g}\n"
        f"  fastest impact               {res.max_impact_velocity:.3g} m/s\n"
        f"  {res.steps} steps in {res.wall_seconds:.3g} s wall (settling: "
        + (f"{res.settle_steps} steps in {res.settle_seconds:.3g} s)" if not res.settle_reused
           else "a bed settled earlier)")
        + (f"\n  time series written to {payload['out']}" if "out" in payload else "")
        + (f"\n  snapshots written to {payload['vtk']}" if "vtk" in payload else ""))


#: Keys of the integration error estimate (``--error-estimate``), last in the JSON.
ACCURACY_KEYS = ("loss_factor_error", "effective_mass_ratio_error", "accuracy_met",
                 "accuracy_refinements", "realisation_loss_factor_spread",
                 "realisation_effective_mass_ratio_spread", "realisation_dependent")

#: Units of the dimensional keys of ``pdamper dem --json``.
UNITS = {"wall_seconds": "s", "dissipated_energy_per_cycle": "J", "time_step": "s",
         "contact_time": "s", "ledger_per_cycle": "J", "max_impact_velocity": "m/s",
         "excitation_wall_seconds": "s", "settle_seconds": "s", "total_wall_seconds": "s",
         "simulated_time": "s", "min_step": "s", "max_step": "s", "verlet_time": "s"}


def _realisations(sc: Scenario, n: int, *, workers: int | None, serial: bool, force: bool,
                  as_json: bool) -> None:
    """``--realisations N`` (N > 1): the runs on the sweep engine; the top-level
    ``loss_factor``, ``effective_mass_ratio`` and ``dissipated_energy_per_cycle`` are the
    means over the realisations, the other run keys those of the first (seed ``--seed``)."""
    from pdamper.runs.realisations import run_realisations

    result = run_realisations(sc, n, workers=workers, serial=serial, force=force)
    first = dict(result.runs[0])
    first.pop("packing", None)
    rec = result.as_dict()
    mean_keys = ("loss_factor", "effective_mass_ratio", "dissipated_energy_per_cycle")
    means = {k: float(sum(r[k] for r in result.runs) / n) for k in mean_keys}
    payload = {**first, **means, "statistic": "mean", "realisations": rec, "units": UNITS,
               **metadata(sc, seed=int(sc.dem.seed))}
    damper = sc.damper()
    eta, mass = rec["loss_factor"], rec["effective_mass_ratio"]
    human = (
        f"DEM, {damper.count} spheres, f = {sc.excitation.frequency:g} Hz, "
        f"X = {sc.excitation.amplitude * 1e3:g} mm, {n} realisations (seeds "
        f"{result.seeds[0]}-{result.seeds[-1]}) in {result.seconds:.3g} s wall "
        + ("in this process\n" if serial else f"on {result.workers} workers\n")
        + f"  effective loss factor        mean {eta['mean']:.4g}, std {eta['std']:.2g}, "
        f"range {eta['min']:.4g} - {eta['max']:.4g}\n"
        f"  effective mass ratio         mean {mass['mean']:.4g}, std {mass['std']:.2g}, "
        f"range {mass['min']:.4g} - {mass['max']:.4g}")
    emit(payload, as_json, human)


def _uncertainty_run(sc, n: int, seed: int, as_json: bool, *, workers, serial: bool) -> None:
    """``--uncertainty N``: the DEM at the excitation for every sample of the uncertain
    inputs (N (inputs + 2) + 1 runs on the sweep engine, ``--workers``/``--serial``, all
    from the scenario's seed); the top-level keys are the nominal run's answers, the
    spread under ``uncertainty``."""
    from pdamper.errors import InputError
    from pdamper.runs.uncertainty import dem_batch, propagate_scenario

    damper = sc.damper()
    if damper.count < 1:
        raise InputError("particles.count", f"must be in [1, {damper.max_count}] for the DEM, "
                         f"got {damper.count}")
    spread = propagate_scenario(sc, "dem", n, seed,
                                batch=dem_batch(sc, workers=workers, serial=serial))
    nominal = {k: a.nominal for k, a in spread.answers.items()}
    payload = {**nominal, "statistic": "nominal", "uncertainty": spread.as_dict(),
               "units": UNITS, **metadata(sc, seed=int(sc.dem.seed))}
    human = (f"DEM, {damper.count} spheres, f = {sc.excitation.frequency:g} Hz, "
             f"X = {sc.excitation.amplitude * 1e3:g} mm, nominal loss factor "
             f"{nominal['loss_factor']:.4g} ("
             + ("in this process" if serial else "on the sweep engine") + ")\n"
             + "\n".join(_uncertainty.lines(spread, {
                 "effective_mass": (1e3, "g"), "dissipated_energy_per_cycle": (1e3, "mJ")})))
    emit(payload, as_json, human)
