"""``pdamper simulate``: free vibration of the structure carrying the damper."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from pdamper.cli import _load_history, _uncertainty
from pdamper.cli._common import (
    BaseAccelerationOpt,
    ForceOpt,
    JsonOpt,
    LoadAtOpt,
    LoadOpt,
    ModelOpt,
    ModesOpt,
    RunUpOpt,
    ScenarioOpt,
    TailOpt,
    UnbalanceOpt,
    check_output,
    check_plot,
    emit,
    figure_last,
    key_help,
    load,
    metadata,
    plot_param,
)
from pdamper.errors import InputError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from pdamper.io.scenario import Scenario


def _run_payload(res, seconds: float) -> dict:
    amp, zeta = res.damping_ratio
    out = {
        "model": res.model,
        "peaks": [{"time": float(t), "amplitude": float(a)}
                  for t, a in zip(res.peak_times, res.peak_amplitudes, strict=True)],
        "damping_ratio": [{"amplitude": float(a), "zeta": float(z)}
                          for a, z in zip(amp, zeta, strict=True)],
        "final_amplitude": res.final_amplitude,
        "effective_frequency": [float(v) for v in res.effective_frequency],
        "cycles": [{"time": c.time, "amplitude": c.amplitude, "frequency": c.frequency,
                    "mode": c.mode.label if c.mode is not None else "unclassified",
                    "effective_mass": c.effective_mass, "damping": c.damping,
                    "loss_factor": c.loss_factor} for c in res.cycles],
        "wall_seconds": seconds,
        # N modes: each mode's ratio from its own modal coordinate (the sum above beats)
        "damping_per_mode": None if res.damping_per_mode is None
        else [m.as_dict() for m in res.damping_per_mode],
        **({"not_applicable": {"damping_per_mode": "one mode: its damping ratio is the "
                                                   "decay's own (damping_ratio)"}}
           if res.damping_per_mode is None else {}),
    }
    _add_harmonicity(out, res)
    return out


def _add_harmonicity(out: dict, res) -> None:
    """``harmonicity`` and ``near_harmonic`` of a describing-function run
    (:mod:`pdamper.coupling.harmonicity`), their reasons merged into ``not_applicable``."""
    from pdamper.coupling.harmonicity import payload

    extra = payload(res)
    why = extra.pop("not_applicable", {})
    out.update(extra)
    if why:
        out["not_applicable"] = {**out.get("not_applicable", {}), **why}


def _table(label: str, res) -> list[str]:
    _, zeta = res.damping_ratio
    per_mode = res.damping_per_mode
    lines = [f"{label}", "   t [s]   X [mm]   zeta     mode"]
    modes = [c.mode.title if c.mode is not None else "unclassified" for c in res.cycles] \
        or ["(not classified)"] * len(res.peak_times)
    beats = False
    for t, a, z, m in zip(res.peak_times, res.peak_amplitudes, list(zeta) + [float("nan")],
                          modes, strict=False):
        # a growing peak of a beating sum of modes is no damping ratio: not printed as one
        if per_mode is not None and z < 0:
            beats = True
            lines.append(f"  {t:6.3f}  {a * 1e3:7.2f}     n/a*  {m}")
        else:
            lines.append(f"  {t:6.3f}  {a * 1e3:7.2f}  {z:7.4f}  {m}")
    lines.append(f"final amplitude {res.final_amplitude * 1e3:.2f} mm")
    if beats:
        lines.append("* not applicable: the next peak of the sum of modes is higher (the modes "
                     "beat); see the damping per mode")
    if per_mode is not None:
        lines.append("damping per mode (decrement of each modal coordinate; the zeta above is "
                     "the beating sum's):")
        for m in per_mode:
            lines.append(f"  mode {m.mode}: zeta {m.damping_ratio:.4f}" if m.reason is None
                         else f"  mode {m.mode}: not applicable ({m.reason})")
    from pdamper.coupling.harmonicity import of_result

    h = of_result(res)
    warn = None if h is None else h.warning()
    if warn is not None:
        lines.append(warn)
    return lines


def simulate(
    model: ModelOpt = None,
    particles: Annotated[int | None, typer.Option(help=key_help("particles.count",
                                                                "Number of spheres."))] = None,
    duration: Annotated[str | None, typer.Option(help=key_help("simulation.duration",
                                                               "Simulated time, e.g. '2s'."))] = None,
    initial_displacement: Annotated[str | None, typer.Option(
        "--initial-displacement", help=key_help("structure.initial_displacement",
                                                "Release deflection x0, e.g. '-58mm'."))] = None,
    fields: Annotated[Path | None, typer.Option(
        help=key_help("fields.file",
                      "Effective-field map (NetCDF from `pdamper map`) of the fields model."))] = None,
    compare: Annotated[str | None, typer.Option(
        help="Several models overlaid, e.g. 'analytic,fields,dem'.")] = None,
    measured: Annotated[Path | None, typer.Option(
        help="Measured end-effector trajectory (CSV with unit headers, e.g. 'time [ms], "
             "displacement [mm]'; or velocity, acceleration).")] = None,
    plot: Annotated[str | None, plot_param(
        "the trajectories and damping ratios (and the phase drift)")] = None,
    out: Annotated[str | None, typer.Option(help="NetCDF file for the trajectory.")] = None,
    modes: ModesOpt = None,
    uncertainty: _uncertainty.UncertaintyOpt = None,
    uncertain: _uncertainty.UncertainOpt = None,
    uncertainty_seed: _uncertainty.UncertaintySeedOpt = 0,
    load_file: LoadOpt = None,
    base_acceleration: BaseAccelerationOpt = None,
    tail: TailOpt = None,
    unbalance: UnbalanceOpt = None,
    run_up: RunUpOpt = None,
    load_at: LoadAtOpt = None,
    realisations: Annotated[str | None, typer.Option(
        "--realisations", help="N realisations of each model that has them: the DEM from N "
        "random packings (seeds dem.seed ... dem.seed + N - 1, in parallel), the effective "
        "fields of a map with realisations from the first N of them; the JSON key "
        "'realisations' holds the band (amplitude at [optimization] at, envelope, damping "
        "ratio per amplitude), the plot shows it (default 1: one run).")] = None,
    at: Annotated[str | None, typer.Option(
        help=key_help("optimization.at",
                      "Time of the realisations' amplitude band, e.g. '0.75s' (default [optimization] "
             "at, the objective time)."))] = None,
    workers: Annotated[int | None, typer.Option(
        help="Worker processes of the local cluster for --realisations (default: every "
             "core).")] = None,
    serial: Annotated[bool, typer.Option(
        "--serial", help="Run the realisations in this process, without dask.")] = False,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Release the structure from x0 and track the decay (paper Sect. 4.2.1, Figs. 7-8)."""
    _load_history.check_one_load(load=load_file, base_acceleration=base_acceleration,
                                 run_up=run_up)
    sc = load(scenario, runs=("simulation",), force=force, **_uncertainty.merged(dict(
        simulation__model=model, particles__count=particles, simulation__duration=duration,
        structure__initial_displacement=initial_displacement,
        fields__file=None if fields is None else str(fields),
        structure__modes=None if modes is None else str(modes),
        load__force=None if load_file is None else str(load_file),
        load__base_acceleration=None if base_acceleration is None
        else str(base_acceleration), load__tail=tail, load__unbalance=unbalance,
        load__run_up=run_up, load__at=load_at, optimization__at=at), uncertain))
    _check_uncertainty(sc, uncertainty, force)
    out_path = check_output(out)
    plot_path = check_plot(plot)
    names = _model_names(sc, compare, force)
    damper = sc.damper()
    models = {n: sc.model(n, damper) for n in names}  # all built (and checked) before any run
    n_real = _realisation_count(sc, realisations, uncertainty)
    if sc.load.given:  # a load history instead of the release (docs/forced.md)
        _run_load_history(sc, models, out_path, plot_path, as_json, force,
                          (uncertainty, uncertainty_seed), measured=measured,
                          duration=duration, initial_displacement=initial_displacement)
        return
    _check_release_options(tail, workers)
    banded = _banded_models(sc, models, n_real, force) if n_real > 1 else []
    aligned = None if measured is None else _aligned(sc, measured)
    _release(sc, models, banded, n_real, aligned, out_path, plot_path, as_json,
             compared=compare is not None, uncertainty=uncertainty,
             uncertainty_seed=uncertainty_seed, workers=workers, serial=serial, force=force)


def _release(sc: Scenario, models: dict[str, Any], banded: list[str], n_real: int,
             aligned: Any, out: Path | None, plot: Path | None, as_json: bool, *,
             compared: bool, uncertainty: int | None, uncertainty_seed: int,
             workers: int | None, serial: bool, force: bool) -> None:
    """The release runs of every model, their outputs (``--out``, ``--plot``), the JSON
    and the text (``compared``: ``--compare`` given)."""
    names = list(models)
    structure = sc.structure_model()
    x0 = sc.structure.initial_displacement
    runs, seconds, bands = _run_models(sc, structure, models, banded, n_real,
                                       workers=workers, serial=serial, force=force)
    meta = metadata(sc)
    if out is not None:
        _write_trajectory(out, runs[names[0]], bands.get(names[0]), meta)
    payload = {k: v for k, v in _run_payload(runs[names[0]], seconds[names[0]]).items()
               if k != "model"}
    payload["units"] = {"time": "s", "amplitude": "m", "frequency": "Hz",
                        "effective_mass": "kg", "damping": "kg/s", "wall_seconds": "s"}
    if compared:
        payload["models"] = {n: _run_payload(r, seconds[n]) for n, r in runs.items()}
        for n, b in bands.items():
            payload["models"][n]["realisations"] = b.as_dict()
    if names[0] in bands:  # the run keys above are then the first realisation's
        payload["realisations"] = bands[names[0]].as_dict()
    comparisons: dict[str, Any] = {}
    if aligned is not None:
        from pdamper.coupling.comparison import compare_with_measurement

        comparisons = {n: compare_with_measurement(r, aligned) for n, r in runs.items()}
        payload["comparison"] = _comparison_payload(aligned, x0, comparisons)
    spread = None
    if uncertainty is not None:
        from pdamper.cli._uncertainty import propagate

        spread = propagate(sc, "level3", uncertainty, uncertainty_seed)
        payload["uncertainty"] = spread.as_dict()
    payload.update(meta)
    lines = _human(structure, x0, models, runs, seconds, bands, aligned, comparisons, spread)
    emit(payload, as_json, "\n".join(lines))  # the results first: a figure cannot lose them
    if plot is not None:
        figure_last(lambda: _figure(runs, aligned, comparisons, bands), plot)


def _check_uncertainty(sc: Scenario, uncertainty: int | None, force: bool) -> None:
    """``--uncertainty`` checked, and the sampled model refused, before any run."""
    if sc.load.given:  # the response to the load history: its runs' cost and model
        history = sc.load.history()
        _uncertainty.check(sc, "load", uncertainty, force, history=history, tail=sc.load.tail)
        if uncertainty is not None:
            from pdamper.runs.uncertainty import load_answers

            load_answers(sc, history, sc.load.tail)
        return
    _uncertainty.check(sc, "level3", uncertainty, force)
    if uncertainty is not None:  # the sampled model refused before any run
        from pdamper.runs.uncertainty import level3_answers

        level3_answers(sc)


def _check_release_options(tail: str | None, workers: int | None) -> None:
    """The options of the release run: no ``--tail`` (a load history's), ``--workers``
    at least 1."""
    if tail is not None:
        raise InputError("load.tail", "is the free vibration after a load history: give "
                         "--load or --base-acceleration")
    if workers is not None and workers < 1:
        raise InputError("workers", f"must be a whole number >= 1, got {workers}")


def _aligned(sc: Scenario, measured: Path) -> Any:
    """The measured trajectory of ``--measured``, aligned to its release and checked
    against the scenario's x0 before any run."""
    from pdamper.coupling.measurement import align_measurement, check_release_scale
    from pdamper.io.measured import read_measured

    aligned = align_measurement(read_measured(measured))
    check_release_scale(aligned, sc.structure.initial_displacement)  # before any run
    return aligned


def _model_names(sc: Scenario, compare: str | None, force: bool) -> list[str]:
    """The models of the run: the scenario's, or those ``--compare`` names (distinct, each
    one's resources checked before any run)."""
    names = [sc.simulation.model]
    if compare is not None:
        names = [n.strip() for n in compare.split(",") if n.strip()]
        if not names or len(set(names)) != len(names):
            raise InputError("compare", f"expected distinct model names such as "
                             f"'analytic,fields,dem', got {compare!r}")
        from pdamper.runs.resources import check_resources

        for n in names:  # what each compared model implies, before any run
            check_resources(sc, "simulation", n, force)
    return names


def _realisation_count(sc: Scenario, realisations: str | None,
                       uncertainty: int | None) -> int:
    """``--realisations`` as a count (1: one run), refused above 1 with a load history or
    ``--uncertainty``."""
    n_real = 1
    if realisations is not None:
        from pdamper.runs.realisations import parse_count

        n_real = parse_count(realisations)
    if n_real > 1 and (sc.load.given or uncertainty is not None):
        raise InputError("realisations", "a band over random packings is of the release's "
                         "free vibration alone: must be 1 with "
                         + ("--load / --base-acceleration" if sc.load.given
                            else "--uncertainty") + f", got {n_real}")
    return n_real


def _run_load_history(sc: Scenario, models: dict[str, Any], out: Path | None,
                      plot: Path | None, as_json: bool, force: bool,
                      uncertainty: tuple[int | None, int] = (None, 0),
                      **release: object) -> None:
    """The run under a load history (docs/forced.md), refusing the ``release`` options
    (``measured``, ``duration``, ...) that belong to the release alone."""
    from pdamper.cli import _load_history
    for name, given in release.items():
        if given is not None:
            raise InputError(name, "a load history starts from rest and lasts the "
                             "record plus --tail: leave out --"
                             + name.replace("_", "-"))
    _load_history.run(sc, models, sc.load.history(), sc.load.tail, out, plot, as_json,
                      force, uncertainty=uncertainty)


def _banded_models(sc: Scenario, models: dict[str, Any], n_real: int,
                   force: bool) -> list[str]:
    """The models that get a band of ``n_real`` realisations (the others run once), every
    count and cost judged before any run."""
    from pdamper.runs.realisations import check_level3_realisations, level3_kind

    banded = [n for n, m in models.items() if level3_kind(m) is not None]
    if not banded:
        raise InputError("realisations", f"must be 1 for {', '.join(models)} (no "
                         f"random packing, no map with realisations), got {n_real}")
    for n in banded:
        check_level3_realisations(n_real, sc, n, force=force)
    return banded


def _run_models(sc: Scenario, structure: Any, models: dict[str, Any], banded: list[str],
                n_real: int, *, workers: int | None, serial: bool,
                force: bool) -> tuple[dict[str, Any], dict[str, float], dict[str, Any]]:
    """Each model's release run (a banded model's first realisation), its wall time [s]
    and the bands of the banded models."""
    import time

    from pdamper.coupling import Simulation

    x0 = sc.structure.initial_displacement
    runs: dict[str, Any] = {}
    seconds: dict[str, float] = {}
    bands: dict[str, Any] = {}
    for n, m in models.items():
        t0 = time.perf_counter()
        if n in banded:
            from pdamper.runs.realisations import run_level3_realisations

            bands[n] = run_level3_realisations(sc, n_real, n, workers=workers, serial=serial,
                                               force=force)
            runs[n] = bands[n].runs[0]  # the first realisation (seed dem.seed; map's 0)
        else:
            from pdamper.cli._progress import Spinner  # a coupled DEM run: minutes

            with Spinner(f"{n}: {sc.simulation.duration:g} s of the coupled run",
                         None if getattr(m, "expensive", False) else False):
                runs[n] = Simulation(structure, m, x0).run(sc.simulation.duration,
                                                           sc.simulation.sample_rate)
        seconds[n] = time.perf_counter() - t0
    return runs, seconds, bands


def _write_trajectory(out: Path, first: Any, band: Any, meta: dict) -> None:
    """The first model's trajectory (and its band, if any) to the NetCDF ``out``."""
    from pdamper.files import atomic_write_netcdf

    ds = first.to_dataset()
    if band is not None:  # the first realisation's trajectory and the band
        ds = band.add_to(ds)
    ds.attrs.update(pdamper_version=meta["version"])
    atomic_write_netcdf(out, ds)


def _comparison_payload(aligned: Any, x0: float, comparisons: dict[str, Any]) -> dict:
    """The JSON ``comparison``: the aligned measurement and each model's errors."""
    amp, zeta = aligned.damping_ratio
    return {
        "measured": {
            "file": aligned.source, "quantity": aligned.quantity,
            "time_offset": aligned.time_offset, "static_offset": aligned.static_offset,
            "initial_deflection": aligned.initial_deflection,
            "simulated_initial_deflection": x0,
            "peaks": [{"time": float(t), "amplitude": float(a)} for t, a in
                      zip(aligned.peak_times, aligned.peak_amplitudes, strict=True)],
            "damping_ratio": [{"amplitude": float(a), "zeta": float(z)}
                              for a, z in zip(amp, zeta, strict=True)],
        },
        "models": {n: c.as_dict() for n, c in comparisons.items()},
        "units": {"peak_rms_error": "m", "peak_rms_relative": "1", "time_drift": "s",
                  "phase_drift": "rad", "zeta": "1"},
    }


def _human(structure: Any, x0: float, models: dict[str, Any], runs: dict[str, Any],
           seconds: dict[str, float], bands: dict[str, Any], aligned: Any,
           comparisons: dict[str, Any], spread: Any) -> list[str]:
    """The human-readable text: the structure, each model's decay table (and band), the
    comparison with the measurement and the uncertainty."""
    if hasattr(structure, "mass"):  # the 1-DOF of Eq. (23)
        on = f"M={structure.mass:.4g} kg, K={structure.stiffness:g} N/m"
    else:
        on = f"{structure.modes} mode(s) at " + ", ".join(f"{f:.4g}" for f in
                                                          structure.frequencies) + " Hz"
    lines = [f"on {on}; x0 = {x0 * 1e3:g} mm"]
    for n, r in runs.items():
        lines += _table(f"{models[n]!r} ({seconds[n]:.2f} s)"
                        + (" first realisation" if n in bands else ""), r)
        if n in bands:
            b = bands[n]
            a = b.amplitude_at()
            lines.append(f"{b.count} realisations: amplitude at {b.at:g} s "
                         f"{a['mean'] * 1e3:.2f} mm (std {a['std'] * 1e3:.2f}, "
                         f"min {a['min'] * 1e3:.2f}, max {a['max'] * 1e3:.2f} mm)")
    if aligned is not None:
        lines.append(f"measured {aligned.source}: released at {aligned.time_offset:.4f} s, "
                     f"x0 = {aligned.initial_deflection * 1e3:.2f} mm")
        for n, c in comparisons.items():
            lines.append(f"  {n}: peak RMS error {c.peak_rms_error * 1e3:.3f} mm "
                         f"({c.peak_rms_relative * 100:.2f} %), zeta RMS error "
                         f"{c.zeta_rms_error:.4f}, phase drift {c.final_phase_drift:+.3f} rad "
                         f"after {c.peaks} peaks")
    if spread is not None:
        lines += _uncertainty.lines(spread, {"amplitude_at": (1e3, "mm"),
                                             "final_amplitude": (1e3, "mm")})
    return lines


def _figure(runs: dict, aligned, comparisons: dict, bands: dict) -> Figure:
    """The figure of ``--plot`` (written after the results)."""
    from matplotlib.figure import Figure

    from pdamper import plots

    panels = 3 if aligned is not None else 2
    fig = Figure(figsize=(11, 3.6 * panels), layout="constrained")
    axes = fig.subplots(panels, 1)
    single = {n: r for n, r in runs.items() if n not in bands}
    for n, b in bands.items():  # a model with realisations is drawn as its band
        plots.plot_trajectory_band(b, ax=axes[0], label=n)
        plots.plot_damping_ratio_band(b, ax=axes[1], label=n)
    plots.plot_model_trajectories(single, aligned, comparisons, ax=axes[0])
    axes[0].set_title("trajectory of the observation point")
    plots.plot_model_damping_ratios(single, aligned, comparisons, ax=axes[1])
    axes[1].set_title("damping ratio over the amplitude")
    if aligned is not None:
        plots.plot_phase_drift(comparisons, ax=axes[2])
        axes[2].set_title("phase drift against the measurement")
    return fig
