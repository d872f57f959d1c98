"""``pdamper simulate --load`` / ``--base-acceleration``: the structure carrying the damper
under a load history (:mod:`pdamper.coupling.loads`, docs/forced.md)."""

from __future__ import annotations

import time
from pathlib import Path
from typing import TYPE_CHECKING

from pdamper.cli._common import emit, figure_last, metadata

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def check_one_load(**given: object) -> None:
    """Refuse more than one load of the command line (``--load``, ``--base-acceleration``,
    ``--run-up``): each replaces the scenario's load, not one another."""
    from pdamper.errors import InputError

    names = ["--" + k.replace("_", "-") for k, v in given.items() if v is not None]
    if len(names) > 1:
        raise InputError("load", f"give one load, not {' and '.join(names)}")


def response_payload(res, seconds: float) -> dict:
    """JSON of one :class:`~pdamper.coupling.loads.LoadResponse` (SI units), with
    ``harmonicity`` and ``near_harmonic`` (:mod:`pdamper.coupling.harmonicity`)."""
    from pdamper.coupling.harmonicity import payload

    out = {
        "model": res.model,
        **res.summary(),
        "cycles": [{"time": c.time, "amplitude": c.amplitude, "frequency": c.frequency,
                    "mode": c.mode.label if c.mode is not None else "unclassified",
                    "effective_mass": c.effective_mass, "damping": c.damping,
                    "loss_factor": c.loss_factor} for c in res.cycles],
        "wall_seconds": seconds,
    }
    extra = payload(res)
    why = extra.pop("not_applicable", {})
    out.update(extra)
    if why:
        out["not_applicable"] = {**out.get("not_applicable", {}), **why}
    return out


def _point_text(named, structure, load_point_text) -> str:
    """Where the force acts, in words: the damper's point because the scenario asks it
    (``[load] at = "damper"``, ``--load-at damper``) although the structure names a load
    point of its own, or else as :func:`~pdamper.coupling.frf.load_point_text` says."""
    import numpy as np

    shape = getattr(named, "load_shape", None)
    if shape is not None and not np.array_equal(shape, structure.load_shape):
        return "the damper's point (the load's 'at', not the structure's load point)"
    return load_point_text(structure)


def run(sc, models: dict, history, tail: float, out: Path | None, plot: Path | None,
        as_json: bool, force: bool = False,
        uncertainty: tuple[int | None, int] = (None, 0)) -> None:
    """Run every model of ``models`` on ``history``; print, write and plot as the free
    decay does. ``uncertainty``: ``(N, seed)`` of ``--uncertainty`` (N None: none), the
    spread of the first model's answers under the scenario's uncertain inputs."""
    from pdamper.coupling.frf import load_point_text
    from pdamper.coupling.loads import acting_at, check_cost, check_model

    named = sc.structure_model()
    structure = acting_at(named, sc.load.at)
    for m in models.values():  # every compared model, its structure and cost, before any run
        check_model(m, structure)
    from pdamper.runs.resources import check_load_history

    check_load_history(sc, structure, history)  # against the physics limits, before any run
    for m in models.values():
        check_cost(m, structure, history, sc.simulation.sample_rate, tail, force)
    runs, seconds, outside = _run_models(models, structure, history,
                                         sc.simulation.sample_rate, tail)
    names = list(models)
    first = runs[names[0]]
    meta = metadata(sc)
    if out is not None:
        from pdamper.files import atomic_write_netcdf

        ds = first.to_dataset()
        ds.attrs.update(pdamper_version=meta["version"])
        atomic_write_netcdf(out, ds)
    payload = {k: v for k, v in response_payload(first, seconds[names[0]]).items()
               if k != "model"}
    payload["load"] = {"file": history.source, "kind": history.kind,
                       "unit": history.unit, "samples": int(history.time.size),
                       "record_duration": history.duration, "tail": tail,
                       "interpolation": "linear",
                       "point": (_point_text(named, structure, load_point_text)
                                 if history.kind == "force" else "the base")}
    run_up = sc.load.run_up_load()
    if run_up is not None:
        payload["load"]["run_up"] = run_up.as_dict()
    payload["units"] = {"time": "s", "peak": "m", "rms": "m", "peak_acceleration": "m/s^2",
                        "rms_acceleration": "m/s^2", "dissipated_energy": "J",
                        "input_work": "J", "structural_dissipation": "J",
                        "energy_change": "J", "energy_balance_error": "1", "amplitude": "m",
                        "frequency": "Hz", "effective_mass": "kg", "damping": "kg/s",
                        "record_duration": "s", "tail": "s", "wall_seconds": "s",
                        "unbalance": "kg*m", "start_speed": "Hz", "stop_speed": "Hz"}
    if len(runs) > 1:
        payload["models"] = {n: response_payload(r, seconds[n]) for n, r in runs.items()}
        for n, record in outside.items():
            payload["models"][n]["fields_outside"] = record
    if names[0] in outside:
        payload["fields_outside"] = outside[names[0]]
    spread = None
    if uncertainty[0] is not None:
        from pdamper.cli._uncertainty import propagate

        spread = propagate(sc, "load", uncertainty[0], uncertainty[1],
                           model=names[0], history=history, tail=tail)
        payload["uncertainty"] = spread.as_dict()
    payload.update(meta)
    what = "force" if history.kind == "force" else "base acceleration"
    where = f" at {payload['load']['point']}" if history.kind == "force" else ""
    lines = [f"{what} {history.source}{where}: {history.time.size} samples over "
             f"{history.duration:g} s (+ {tail:g} s free tail), linear between samples"]
    for n, r in runs.items():
        lines += _run_lines(models[n], r, seconds[n], history.kind)
        if n in outside:
            lines.append(f"  {models[n].outside_warning(outside[n])}")
    if spread is not None:
        from pdamper.cli._uncertainty import lines as spread_lines

        lines += spread_lines(spread, {"peak": (1e3, "mm"), "rms": (1e3, "mm"),
                                       "dissipated_energy": (1.0, "J")})
        lines.append("uncertainty band: the envelope, the largest |x| in each of "
                     f"{len(spread.bands['envelope']['time'])} windows (JSON "
                     "uncertainty.bands.envelope)")
    emit(payload, as_json, "\n".join(lines))  # the results first: a figure cannot lose them
    if plot is not None:
        figure_last(lambda: _figure(runs, history, spread), plot)


def _run_models(models: dict, structure, history, sample_rate: float, tail: float):
    """Every model's run of ``history``: the responses, their wall seconds, and for a
    fields map the record of its lookups outside its range (by model name)."""
    from pdamper.coupling.loads import run_load

    runs, seconds, outside = {}, {}, {}
    for n, m in models.items():
        t0 = time.perf_counter()
        if hasattr(m, "reset_outside"):  # a fields map: its lookups outside its range
            m.reset_outside()
        runs[n] = run_load(m, structure, history, sample_rate, tail)
        seconds[n] = time.perf_counter() - t0
        record = m.outside_record() if hasattr(m, "outside_record") else None
        if record is not None:
            outside[n] = record
    return runs, seconds, outside


def _run_lines(model, r, seconds: float, kind: str) -> list[str]:
    """The text of one model's run, and a line where its describing function rests on a
    motion that is not near-harmonic (:mod:`pdamper.coupling.harmonicity`)."""
    from pdamper.coupling.harmonicity import of_result

    rel = " (relative to the base)" if kind != "force" else ""
    lines = [f"{model!r} ({seconds:.2f} s): peak {r.peak * 1e3:.3f} mm, "
             f"RMS {r.rms * 1e3:.3f} mm{rel}; acceleration peak "
             f"{r.peak_acceleration:.4g} m/s^2, RMS {r.rms_acceleration:.4g} m/s^2; "
             f"damper dissipated {r.dissipated_energy:.4g} J"
             + (f" in {len(r.cycles)} updates" if r.cycles else "")]
    h = of_result(r)
    warn = None if h is None else h.warning()
    if warn is not None:
        lines.append("  " + warn)
    return lines


def _figure(runs: dict, history, spread=None) -> Figure:
    """The figure of ``--plot`` (written after the results); with ``spread`` the 5-95 %
    band of the envelope under the uncertain inputs."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 10), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    t = history.time - history.time[0]
    axes[0].plot(t, history.values, "k", lw=0.8)
    axes[0].set_ylabel(f"{history.kind.replace('_', ' ')} [{history.unit}]")
    axes[0].set_title("load history (linear between samples)")
    for label, r in runs.items():
        axes[1].plot(r.time, r.displacement * 1e3, lw=0.9,
                     label=f"{label}: peak {r.peak * 1e3:.2f} mm, RMS {r.rms * 1e3:.2f} mm")
        if r.cycles:
            axes[2].plot([c.time for c in r.cycles], [c.loss_factor for c in r.cycles], ".-",
                         lw=0.8, label=f"{label}: {r.dissipated_energy:.3g} J dissipated")
    rel = " relative to the base" if history.kind != "force" else ""
    if spread is not None:
        b = spread.bands["envelope"]
        axes[1].fill_between(b["time"], b["p5"] * 1e3, b["p95"] * 1e3, color="C4", alpha=0.3,
                             lw=0, label="envelope |x|, 5-95 % under the uncertain inputs")
    axes[1].set_ylabel(f"displacement{rel} [mm]")
    axes[1].set_title("response of the structure")
    axes[1].legend(fontsize="x-small", loc="upper right")
    axes[2].set_ylabel("damper loss factor eta [-]")
    axes[2].set_xlabel("time t [s]")
    axes[2].set_title("damper at its updates")
    if any(r.cycles for r in runs.values()):
        axes[2].legend(fontsize="x-small", loc="upper right")
    return fig
