"""Realisations of a DEM run: the same damper and excitation from N independent random
packings, run in parallel on the sweep engine (:func:`pdamper.sweep.run_sweep`).

A DEM result depends on the realisation (the random initial packing); the spread over
packings says how sure one run's loss factor and effective mass ratio are. Realisation
``k`` (``k = 0 .. N-1``) starts from the random packing of seed ``seed + k``, so the first
is the single run of that seed, and every realisation can be run again on its own with
``pdamper dem --seed``.

Example::

    from pdamper.io.scenario import load_scenario
    from pdamper.reports.realisations import run_realisations

    sc = load_scenario(None, {"dem.packing": "random", "particles.count": 16})
    res = run_realisations(sc, 5, serial=True)
    res.statistics("loss_factor")   # {"mean", "std", "min", "max", "values"}
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from pdamper import resources
from pdamper.errors import InputError

#: The quantities whose spread over the realisations is reported.
SPREAD_KEYS = ("loss_factor", "effective_mass_ratio")

#: Usual number of realisations (a count far above it is judged by its cost first).
USUAL_REALISATIONS = 5


def run_summary(model, response) -> dict:
    """The scalar summary of one Level II DEM response (``pdamper dem --json``'s run keys):
    loss factor, effective mass ratio, dissipated energy per cycle [J], energy ledger [J],
    stationarity, motion mode and the run's diagnostics (SI units): the keys of
    :meth:`DEMResult.summary <pdamper.dem.DEMResult.summary>` (``steps`` and
    ``wall_seconds`` are the excitation's; ``settle_steps``, ``settle_seconds`` the
    settling's; ``total_steps``, ``total_wall_seconds`` both)."""
    r = response
    res = r.details.item()
    st = r.diagnostics["stationarity"].item()
    motion = r.diagnostics["motion"].item()
    skip, span = st.first_cycle - 1, st.last_cycle - st.first_cycle + 1
    out = {
        **res.summary(),  # the run's own keys (steps, wall times, ...), one meaning each
        "loss_factor": float(r.loss_factor),
        "effective_mass_ratio": float(r.effective_mass_ratio),
        "dissipated_energy_per_cycle": float(r.dissipated_energy_per_cycle),
        "ledger_per_cycle": res.ledger_per_cycle(skip, span),
        "stationary": bool(st.stationary),
        "steady_reason": st.reason,
        "cycles": st.cycles,
        "averaged_cycles": [st.first_cycle, st.last_cycle],
        "quiet_window": bool(st.quiet),
        "loss_factor_stderr": st.stderr,
        "motion_mode": motion.mode.label,
        "subharmonic_order": motion.subharmonic_order,
        "mode_reason": motion.reason,
    }
    if model.error_estimate:
        d = r.diagnostics
        out.update(loss_factor_error=float(d["loss_factor_error"].item()),
                   effective_mass_ratio_error=float(d["effective_mass_ratio_error"].item()),
                   accuracy_met=bool(d["accuracy_met"].item()),
                   accuracy_refinements=int(d["accuracy_refinements"].item()))
    return out


def with_seed(scenario, seed: int):
    """``scenario`` with the DEM seed ``seed`` (everything else unchanged)."""
    return scenario.model_copy(update={"dem": scenario.dem.model_copy(update={"seed": seed})})


def realisation_point(params: dict, *, scenario) -> dict:
    """One realisation (runs on a sweep worker): the DEM of ``scenario`` at the
    excitation's f, X from the random packing of seed ``params["seed"]``; its
    :func:`run_summary`."""
    sc = with_seed(scenario, int(params["seed"]))
    damper = sc.damper()
    model = sc.model("dem", damper)
    r = model.response(sc.excitation.frequency, sc.excitation.amplitude)
    return {**run_summary(model, r), "packing": model.initial_packing()}


def check_realisations(count, scenario=None, *, force: bool = False) -> int:
    """``count`` as a number of realisations: a whole number >= 1 whose implied cost (N
    times one DEM run, judged by :mod:`pdamper.resources`) is within the limits; N > 1
    only from a random packing (the lattice is one realisation).

    Raises
    ------
    InputError
        ``realisations``: not a whole number >= 1, too costly, or N > 1 on the lattice.
    """
    if isinstance(count, bool) or isinstance(count, float) and not count.is_integer():
        raise InputError("realisations", f"must be a whole number >= 1, got {count!r}")
    try:
        n = int(count)
    except (TypeError, ValueError):
        raise InputError("realisations", f"must be a whole number >= 1, "
                         f"got {count!r}") from None
    if n < 1:
        raise InputError("realisations", f"must be a whole number >= 1, got {n}")
    if n == 1 or scenario is None:
        return n
    # the count is judged before any run: N runs of one DEM run's cost each
    one = scenario.excitation_cost("dem")
    resources.require(resources.Cost(
        "the realisations", one.seconds * n, one.memory,
        f"{n:.3g} DEM runs, each {one.detail}",
        (("realisations", n / USUAL_REALISATIONS),), runs=n, longest=one.seconds,
        remedy="ask for fewer realisations"), force)
    model = scenario.model("dem", scenario.damper())
    if model.initial_packing() != "random":
        raise InputError("realisations", f"must be 1 with the lattice packing (the lattice is "
                         f"one realisation), got {n}; use dem.packing = \"random\"")
    return n


@dataclass
class RealisationsResult:
    """N realisations of one DEM run (realisation ``k`` from seed ``seeds[k]``)."""

    seeds: list[int]
    runs: list[dict]
    seconds: float = math.nan
    workers: int = 0
    errors: list[str] = field(default_factory=list)

    @property
    def count(self) -> int:
        return len(self.seeds)

    def statistics(self, name: str) -> dict:
        """``{"mean", "std", "min", "max", "values"}`` of ``name`` over the realisations;
        ``std`` is the sample standard deviation (divisor N - 1; NaN for one)."""
        v = np.array([r[name] for r in self.runs], float)
        return {"mean": float(v.mean()),
                "std": float(v.std(ddof=1)) if v.size > 1 else math.nan,
                "min": float(v.min()), "max": float(v.max()), "values": v.tolist()}

    def as_dict(self) -> dict:
        """The ``realisations`` record of ``pdamper dem --json``."""
        return {"count": self.count, "seeds": list(self.seeds),
                "std_ddof": 1, "seconds": self.seconds, "workers": self.workers,
                **{k: self.statistics(k) for k in SPREAD_KEYS}}


def run_realisations(scenario, count: int, *, workers: int | None = None,
                     scheduler: str | None = None, serial: bool = False,
                     force: bool = False, progress=None) -> RealisationsResult:
    """Run ``count`` realisations of the scenario's DEM run (``[excitation]``, ``[dem]``)
    from seeds ``dem.seed, dem.seed + 1, ...`` on the sweep engine (a local dask cluster
    of every core, ``workers`` processes, an existing ``scheduler``, or ``serial`` in this
    process).

    Raises
    ------
    InputError
        A bad count (:func:`check_realisations`).
    RuntimeError
        A realisation failed (its error).
    """
    from pdamper.sweep import run_sweep

    n = check_realisations(count, scenario, force=force)
    seed0 = int(scenario.dem.seed)
    seeds = [seed0 + k for k in range(n)]
    res = run_sweep(functools.partial(realisation_point, scenario=scenario),
                    [{"seed": s} for s in seeds], retries=0, workers=workers,
                    scheduler=scheduler, serial=serial, progress=progress)
    bad = [(p.params["seed"], p.error) for p in res.points if not p.ok]
    if bad:
        raise RuntimeError(f"realisation of seed {bad[0][0]} failed: {bad[0][1]}")
    return RealisationsResult(seeds, [p.values for p in res.points], res.seconds,
                              res.workers)
