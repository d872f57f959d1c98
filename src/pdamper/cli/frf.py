"""``pdamper frf``: forced response of the structure carrying the damper (docs/forced.md)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import numpy as np
import typer

from pdamper.cli import _uncertainty
from pdamper.cli._common import (
    JsonOpt,
    ModelOpt,
    ModesOpt,
    ScenarioOpt,
    check_output,
    check_plot,
    emit,
    figure_last,
    key_help,
    load,
    metadata,
    plot_param,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from pdamper.coupling.frf import FRFResult

#: Default load (without --force, --unbalance, --base and a [frf] load). Without
#: --frequency and [frf] frequency the frequencies span every mode of the structure
#: (:func:`pdamper.coupling.frf.default_frequencies`); DEFAULT_FREQUENCY is the paper's
#: grid (its structure's resonance near 5.5 Hz), for the record.
DEFAULT_FORCE = "2N"
DEFAULT_FREQUENCY = "3Hz:9Hz:121"


def parse_load(force: str | None, base: str | None, unbalance: str | None = None,
               default: str | None = DEFAULT_FORCE):
    """The :class:`~pdamper.coupling.frf.HarmonicLoad` of ``--force``, ``--unbalance``
    (``m e``, e.g. ``1.76kg*mm``) or ``--base`` (a length, or an acceleration: ``0.3g`` is
    0.3 standard gravities); none given: a force ``default`` (None: no load)."""
    from pdamper.coupling.frf import HarmonicLoad
    from pdamper.errors import InputError

    given = [n for n, v in (("force", force), ("unbalance", unbalance), ("base", base))
             if v is not None]
    if len(given) > 1:
        raise InputError(given[-1], f"give one of --force, --unbalance and --base, not "
                         f"{' and '.join('--' + g for g in given)}")
    if unbalance is not None:
        return HarmonicLoad.parse(unbalance, "unbalance")
    if base is not None:
        return HarmonicLoad.parse(base, "base")
    if force is None and default is None:
        return None
    return HarmonicLoad.parse(DEFAULT_FORCE if force is None else force, "force")


#: The command's options (module level: the signature stays readable).
_ForceOpt = Annotated[str | None, typer.Option(
    "--force", help=key_help("frf.force", "Harmonic force amplitude at the structure's "
                             "load point (the damper's point unless the modes name a "
                             "load point), e.g. '2N' (default 2 N)"))]
_UnbalanceOpt = Annotated[str | None, typer.Option(
    "--unbalance", help=key_help("frf.unbalance", "Rotating unbalance m e at the load "
                                 "point instead, e.g. '1.76kg*mm': the force m e Omega^2 "
                                 "at each speed"))]
_BaseOpt = Annotated[str | None, typer.Option(
    help="Harmonic base motion instead: displacement ('1mm') or acceleration ('0.3g') "
         "amplitude (one-mode structures; scenario keys frf.base_displacement, "
         "frf.base_acceleration).")]
_LoadAtOpt = Annotated[str | None, typer.Option(
    "--load-at", help=key_help("frf.at", "Where the force or unbalance acts: load (the "
                               "structure's load point) or damper"))]
_FrequencyOpt = Annotated[str | None, typer.Option(
    help=key_help("frf.frequency", "Frequencies 'start:stop:count' (e.g. '3Hz:9Hz:121', "
                  "'360rpm:2400rpm:100') or one; default every mode of the structure, "
                  "each resonance resolved for its damping"))]
_SweepOpt = Annotated[str | None, typer.Option(
    help=key_help("frf.sweep", "Stepped-sine direction: up, down or both (default "
                  "both)"))]
_MaxCyclesOpt = Annotated[int | None, typer.Option(
    "--max-cycles", help="Most load cycles per frequency step of the stepped sine "
                         "(default 2000; the DEM 60).")]
_AllowCostOpt = Annotated[bool, typer.Option(
    "--allow-cost", help="Allow a response whose estimated memory or run time is above the "
                         "usual limits (2 GiB, 1 h), up to what this machine can hold; "
                         "every other command's --force (here --force is the load).")]
_GravityOpt = Annotated[str | None, typer.Option(
    "--gravity", help=key_help("excitation.gravity", "g, e.g. '9.81 m/s^2' (default); "
                               "'0 m/s^2' for a structure in orbit"))]
_RealisationsOpt = Annotated[str | None, typer.Option(
    "--realisations", help="The response from N realisations of the damper: the DEM from "
    "N random packings (seeds dem.seed ... dem.seed + N - 1), the fields from the first "
    "N realisations of their map; the JSON key 'realisations' holds the band of each "
    "sweep and of the peak (default 1).")]


def frf(
    model: ModelOpt = None,
    force: _ForceOpt = None,
    unbalance: _UnbalanceOpt = None,
    base: _BaseOpt = None,
    load_at: _LoadAtOpt = None,
    frequency: _FrequencyOpt = None,
    sweep: _SweepOpt = None,
    particles: Annotated[int | None, typer.Option(help=key_help("particles.count",
                                                                "Number of spheres."))] = None,
    fields: Annotated[Path | None, typer.Option(
        help=key_help("fields.file",
                      "Effective-field map (NetCDF from `pdamper map`) of the fields model."))] = None,
    max_cycles: _MaxCyclesOpt = None,
    plot: Annotated[str | None, plot_param("the amplitude and phase against frequency")] = None,
    out: Annotated[str | None, typer.Option(help="NetCDF file of the response.")] = None,
    modes: ModesOpt = None,
    allow_cost: _AllowCostOpt = False,
    uncertainty: _uncertainty.UncertaintyOpt = None,
    uncertain: _uncertainty.UncertainOpt = None,
    uncertainty_seed: _uncertainty.UncertaintySeedOpt = 0,
    realisations: _RealisationsOpt = None,
    gravity: _GravityOpt = None,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Steady amplitude and phase under a harmonic force, unbalance or base motion against
    frequency: harmonic balance (every branch) and stepped sines up and down."""
    from pdamper.errors import check_whole
    from pdamper.runs.resources import check_frf

    sc = load(scenario, **_uncertainty.merged(dict(
        simulation__model=model, particles__count=particles,
        fields__file=None if fields is None else str(fields),
        structure__modes=None if modes is None else str(modes), frf__at=load_at,
        excitation__gravity=gravity), uncertain))
    load_, freqs, sweep, source = _resolved(
        sc, parse_load(force, base, unbalance, default=None),
        None if frequency is None else _frequencies(frequency), _checked_sweep(sweep))
    if max_cycles is not None:
        check_whole("max_cycles", max_cycles, 1)
    n_real = _realisation_count(sc, model, realisations, uncertainty)
    # the cost of every frequency, sweep, cycle and mode, judged before any is solved
    check_frf(sc, model, freqs, load_, max_cycles=max_cycles, sweep=sweep, force=allow_cost,
              require=None if n_real == 1 else _scaled(n_real))
    _check_uncertainty(sc, model, uncertainty, allow_cost, len(freqs))
    out_path = check_output(out)
    plot_path = check_plot(plot)
    res, band = _solve(sc, model, n_real, load_, freqs, sweep, max_cycles)
    meta = metadata(sc)
    if out_path is not None:
        _write_response(out_path, res, meta)
    payload, text = _payload(res, source, load_, band)
    spread = None
    if uncertainty is not None:
        spread = _uncertainty.propagate(sc, "frf", uncertainty, uncertainty_seed, model=model,
                                        load=load_, frequency=freqs)
        payload["uncertainty"] = spread.as_dict()
        text += _uncertainty.lines(spread, {"peak": (1e3, "mm"), "rms": (1e3, "mm"),
                                            "peak_frequency": (1.0, "Hz")})
        text.append("uncertainty band: the largest stable harmonic-balance amplitude at each "
                    "frequency (JSON uncertainty.bands.amplitude)")
    payload.update(meta)
    emit(payload, as_json, "\n".join(text))  # the results first: a figure cannot lose them
    if plot_path is not None:
        _figure(res, plot_path, spread, band)


def _checked_sweep(sweep: str | None) -> str | None:
    from pdamper.errors import InputError

    if sweep is not None and sweep not in ("up", "down", "both"):
        raise InputError("sweep", f"must be up, down or both, got {sweep!r}")
    return sweep


def _solve(sc, model: str | None, n_real: int, load_, freqs, sweep: str,
           max_cycles: int | None) -> tuple:
    """The forced response (realisation 0 where ``n_real`` > 1) and the band over the
    realisations (None for one run)."""
    from pdamper.coupling.frf import frequency_response

    structure = _acting(sc)
    if n_real > 1:  # realisation 0 is the run reported; the band is over all of them
        from pdamper.cli._progress import Bar
        from pdamper.runs.realisations import realisation_models

        models, which = realisation_models(sc, n_real, model)
        runs = []
        with Bar("realisations of the forced response") as progress:  # stderr only
            for mk in models:
                runs.append(frequency_response(mk, structure, load_, freqs, sweep=sweep,
                                               max_cycles=max_cycles))
                if progress is not None:
                    progress(len(runs), len(models))
        return runs[0], _band(runs, which)
    from pdamper.cli._progress import frf_steps  # the DEM's steps: minutes (stderr only)

    with frf_steps(len(freqs) * (2 if sweep == "both" else 1)) as steps:
        res = frequency_response(sc.model(None, sc.damper()), structure, load_, freqs,
                                 sweep=sweep, max_cycles=max_cycles,
                                 progress=None if steps is None else steps.step)
    return res, None


def _payload(res, source: str, load_, band: dict | None) -> tuple[dict, list[str]]:
    """The JSON of the response (without the scenario's metadata) and its text lines."""
    from pdamper.coupling.decrement import frf_resonances

    payload = res.as_dict()
    payload["frf_inputs"] = payload.pop("inputs")  # "inputs" is the scenario's, as everywhere
    payload["frf_inputs"]["frequency_source"] = source
    payload["resonances"] = frf_resonances(res)  # each resonance's zeta, with and without
    payload["units"] = {"frequency": "Hz", "amplitude": "m", "stroke": "m", "phase": "rad",
                        "loss_factor": "1", "effective_mass": "kg", "wall_seconds": "s",
                        "load": load_.unit}
    from pdamper.coupling.harmonicity import frf_summary, frf_warning

    near = frf_summary(res)
    payload["near_harmonic"] = near["near_harmonic"]
    if "not_applicable" in near:
        payload.setdefault("not_applicable", {}).update(near["not_applicable"])
    text = _table(res)
    warn = frf_warning(res)
    if warn is not None:
        text.append(warn)
    marks = payload.get("assumptions")
    if marks is not None and marks["flagged"]:
        from pdamper.analysis.analytical import assumption_line

        fl = marks["frequencies"]
        text.append(f"{assumption_line(marks, 'answers')} ({fl[0]:g}-{fl[-1]:g} Hz; "
                    "o in the figure, JSON assumptions_hold per row)")
    if band is not None:
        payload["realisations"] = band
        text += [f"{band['count']} realisations ({'seeds ' if 'seeds' in band else 'map '}"
                 f"{band.get('seeds', band.get('map_realisations'))}; the table is the first): "
                 + "; ".join(f"{name} peak {p['mean'] * 1e3:.3g} +- {p['std'] * 1e3:.2g} mm "
                             f"[{p['min'] * 1e3:.3g}, {p['max'] * 1e3:.3g}]"
                             for name, p in band["peak"].items())]
    return payload, text


def _realisation_count(sc, model: str | None, realisations: str | None,
                       uncertainty: int | None) -> int:
    """``--realisations`` as a count (1: one run), judged with the model before any run."""
    if realisations is None:
        return 1
    from pdamper.errors import InputError
    from pdamper.runs.realisations import check_realisation_models, parse_count

    n = check_realisation_models(parse_count(realisations), sc, model)
    if n > 1 and uncertainty is not None:
        raise InputError("realisations", "must be 1 with --uncertainty (a spread over the "
                         f"packings or over the inputs, one at a time), got {n}")
    return n


def _scaled(n: int):
    """The forced response's cost check for ``n`` realisations of it."""
    import functools

    from pdamper import resources
    from pdamper.runs.realisations import scaled_require
    from pdamper.runs.resources import FRF_OVERRIDE

    return scaled_require(n, functools.partial(resources.require, override=FRF_OVERRIDE))


def _band(runs: list, which: dict) -> dict:
    """The band of the forced responses of the realisations: each sweep's amplitude
    (mean, std with divisor N - 1, min, max per frequency) and its peak, every
    realisation's peak (SI)."""
    from pdamper.runs.realisations import spread

    out: dict = {"count": len(runs), **which, "std_ddof": 1, "sweeps": {}, "peak": {}}
    for name in runs[0].sweeps:
        a = np.array([r.sweeps[name].amplitude for r in runs], float)
        out["sweeps"][name] = {"amplitude_mean": a.mean(0).tolist(),
                               "amplitude_std": a.std(0, ddof=1).tolist(),
                               "amplitude_min": a.min(0).tolist(),
                               "amplitude_max": a.max(0).tolist()}
        out["peak"][name] = spread(a.max(axis=1))
    return out


def _check_uncertainty(sc, model: str | None, n: int | None, force: bool,
                       frequencies: int) -> None:
    """``--uncertainty N`` judged before any run: the inputs, the sampled fidelity (a
    cheap one with harmonic balance) and the cost of N (d + 2) + 1 forced responses."""
    _uncertainty.check(sc, "frf", n, force, frequencies=frequencies)
    if n is not None:
        from pdamper.runs.uncertainty import frf_answers

        frf_answers(sc, None, [1.0], model)  # refuses an expensive fidelity before any run


def _resolved(sc, given, freqs, sweep) -> tuple:
    """The load, frequencies [Hz], sweep direction and the frequencies' source: the command
    line's, else the scenario's ``[frf]``, else the defaults (a force of 2 N; every mode of
    the structure, each resonance resolved for its damping)."""
    load_ = given or sc.frf.load() or parse_load(None, None)
    source = "--frequency" if freqs is not None else (
        "frf.frequency" if sc.frf.frequency is not None else
        "default: every mode of the structure, each resonance resolved for its damping")
    if freqs is None:
        freqs = sc.frf.frequencies(sc.structure_model(), sc.damper().bed_mass)
    return load_, freqs, sweep or sc.frf.sweep, source


def _acting(sc):
    """The scenario's structure with its forces where ``[frf] at`` says."""
    from pdamper.coupling.loads import acting_at

    return acting_at(sc.structure_model(), sc.frf.at, "frf.at")


def _frequencies(text: str) -> np.ndarray | list[float]:
    """The frequencies [Hz] of ``--frequency``: a grid 'start:stop:count' (at most
    ``MAX_FREQUENCIES``, judged before the grid is built) or one frequency > 0."""
    from pdamper.errors import InputError

    if ":" in text:
        from pdamper.coupling.frf import MAX_FREQUENCIES
        from pdamper.io.scenario import grid, parse_axis

        count = parse_axis(text, "Hz", "frequency")[2]  # judged before the grid is built
        if count > MAX_FREQUENCIES:
            raise InputError("frequency", f"at most {MAX_FREQUENCIES} frequencies, got {count}")
        return grid(text, "Hz", "frequency")
    from pdamper.units import parse_quantity

    value = parse_quantity(text, "Hz", "frequency")
    if not value > 0:
        raise InputError("frequency", f"must be > 0 Hz, got {text!r}")
    return [value]


def _write_response(out: Path, res: FRFResult, meta: dict) -> None:
    """The response to the NetCDF ``out``, with the scenario's and the run's inputs."""
    from pdamper.files import atomic_write_netcdf

    ds = res.to_dataset()
    ds.attrs["inputs"] = json.dumps(meta["inputs"])
    ds.attrs["frf_inputs"] = json.dumps(res.inputs)
    atomic_write_netcdf(out, ds)


def _figure(res: FRFResult, path: Path, spread=None, band: dict | None = None) -> None:
    """Amplitude and phase against frequency to ``--plot``; with ``spread`` (an
    uncertainty propagation) the 5-95 % band and the median of the amplitude, with
    ``band`` (realisations) each sweep's range over the realisations."""
    def draw() -> Figure:
        from matplotlib.figure import Figure

        from pdamper.plots.frf import plot_frf

        fig = Figure(figsize=(8, 8.5), layout="constrained")
        axes = fig.subplots(3, 1, sharex=True)
        plot_frf(res, axes=axes)
        if spread is not None:
            b = spread.bands["amplitude"]
            axes[0].fill_between(b["frequency"], b["p5"] * 1e3, b["p95"] * 1e3, color="C4",
                                 alpha=0.25, lw=0, label="5-95 % under the uncertain inputs")
            axes[0].plot(b["frequency"], b["p50"] * 1e3, color="C4", lw=1, ls=":",
                         label="median")
            axes[0].legend(fontsize=7)
        if band is not None:
            for k, (name, b) in enumerate(band["sweeps"].items()):
                axes[0].fill_between(res.frequency, np.asarray(b["amplitude_min"]) * 1e3,
                                     np.asarray(b["amplitude_max"]) * 1e3, color=f"C{k}",
                                     alpha=0.2, lw=0, label=f"{name}: range over "
                                     f"{band['count']} realisations")
            axes[0].legend(fontsize=7)
        return fig

    figure_last(draw, path, dpi=110)


def _table(res: FRFResult) -> list[str]:
    from pdamper.coupling.pseudo_force import motion_mode

    ld = res.load
    walls = ", ".join(f"{k} {v:.2f} s" for k, v in res.wall_seconds.items())
    where = res.inputs.get("load_point", "")
    lines = [f"forced response, {res.model} model, {ld.describe()}"
             + (f" at {where}" if where and ld.at_load_point else "")
             + f"; amplitudes [mm] of the output point ({walls})"]
    head = "    f [Hz]  linear"
    if res.harmonic_balance is not None:
        head += "   harmonic balance (s stable, u unstable, e edge)"
    for name in res.sweeps:
        head += f"   {name:>5s}"
    lines.append(head)
    for i, f in enumerate(res.frequency):
        row = f"  {f:8.3f}  {abs(res.linear[i]) * 1e3:6.2f}"
        if res.harmonic_balance is not None:
            hb = res.harmonic_balance
            assert hb.branch is not None  # harmonic balance labels every solution's branch
            cells = [f"{a * 1e3:.2f}{b[0]}" for a, b in zip(hb.amplitude[i], hb.branch[i],
                                                            strict=True) if b]
            row += "   " + f"{' '.join(cells):45s}"
        for c in res.sweeps.values():
            flag = "" if c.steady[i] else "*"
            row += f"  {c.amplitude[i] * 1e3:6.2f}{flag}"
            if not c.steady[i] and c.amplitude_std is not None and c.amplitude_mean is not \
                    None and np.isfinite(c.amplitude_std[i]):
                row += (f" (last windows {c.amplitude_mean[i] * 1e3:.2f} +- "
                        f"{c.amplitude_std[i] * 1e3:.2f})")
        lines.append(row)
    for name, c in res.sweeps.items():
        k = int(np.argmax(c.amplitude))
        md = motion_mode(c.mode[k])
        lines.append(f"{name}: peak {c.amplitude[k] * 1e3:.2f} mm at {res.frequency[k]:g} Hz "
                     f"(stroke {c.stroke[k] * 1e3:.2f} mm, eta {c.loss_factor[k]:.3g}, "
                     f"m_eff {c.effective_mass[k] * 1e3:.1f} g, "
                     f"{md.title if md is not None else 'unclassified'}); "
                     f"{int(np.count_nonzero(~c.steady))} point(s) not steady (*)")
    if any(not np.all(c.steady) for c in res.sweeps.values()):
        lines.append("amplitudes: the first harmonic of the output point over the step's last "
                     "window; * not steady: the mean and standard deviation over its last "
                     "windows show the scatter of that one value")
    return lines

