"""Accuracy of the DEM defaults over the design map: the verification table of docs/verification.md.

Run ``python benchmarks/bench_dem_accuracy.py`` (``--quick``: five points; ``--jobs 2``:
two processes). At each point of a grid that spans the paper's envelope (2-20 Hz x
1-200 mm, 16 / 32 / 192 spheres of the benchmark damper, the fastest corners included) it
runs the paper's procedure (8 cycles after settling, complex power over cycles 3-8):

* ``default``: :class:`pdamper.models.DEMDamper` defaults (Gear, tolerance 1e-5);
* ``converged``: velocity Verlet at a quarter of the default safety (0.005);
* ``refined``: the default at a tenth of its Gear tolerance: the companion run of the
  model's error estimate (:class:`pdamper.models.dem.AccuracyEstimate`), whose bound
  ``2 |default - refined|`` is checked against the deviation from the converged run;
* the same two with every sphere moved by up to 1e-9 m (seeded): the *sensitivity* of the
  point. Where these moves change a converged result by more than 1 %, the bed is
  chaotic or multi-stable there (which state it is in after 8 cycles depends on details
  below any integrator's error): no single run is reproducible to 1 %, and the table
  compares the means of the two runs of each kind instead.

It prints, per point, loss factor and effective mass ratio of both, their deviation
(relative; the loss factor relative to ``max(eta, 0.05)`` so that solid-like points with
``eta ~ 0`` compare absolutely), the sensitivity, the fastest impact, the largest overlap
and the CPU seconds of each run (``time.thread_time``: robust to the load of a shared
machine; one core). Numbers are deterministic; only the CPU times vary between machines.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from concurrent.futures import ProcessPoolExecutor

import numpy as np

#: (f [Hz], X [mm], spheres): corners, edges and interior of the paper's map.
GRID = [
    (2, 1, 32), (2, 200, 32), (20, 1, 32), (20, 200, 32),        # corners
    (11, 1, 32), (11, 200, 32), (2, 50, 32), (20, 32, 32),       # edges
    (10, 32, 32), (8, 80, 32), (18, 50, 32), (5, 100, 32),       # interior
    (10, 15, 32), (6, 15, 32), (12, 10, 32), (14, 15, 32),       # the issue's points
    (2, 200, 16), (20, 200, 16), (20, 1, 16),                    # one layer
    (2, 200, 192), (20, 200, 192), (20, 1, 192), (10, 32, 192),  # full container
]
QUICK = [(20, 1, 32), (20, 32, 32), (18, 50, 32), (10, 32, 32), (20, 200, 16)]
CONVERGED_SAFETY = 0.005
TOLERANCE = 0.01
#: Deviations below this (a tenth of the 1 % target) are not held against the estimate:
#: the converged reference has an error of its own at that level, and a bound that misses a
#: deviation of 0.05 % does not mislead anyone about the 1 % target
RESOLUTION = 1e-3


def run(f: float, x_mm: float, n: int, kind: str, jitter: int) -> dict:
    """One run of the paper's procedure (``kind``: default, converged or refined); the loss
    factor, mass ratio and diagnostics."""
    from pdamper.dem import Container, DEMEngine, EngineSettings, HarmonicMotion, ParticleSet
    from pdamper.dem.inputs import DEFAULT_GEAR_TOLERANCE
    from pdamper.models import DEMDamper
    from pdamper.models.dem import PAPER_CYCLES, REFINEMENT
    from pdamper.parameters import PAPER_DAMPER

    warnings.simplefilter("ignore")
    d = PAPER_DAMPER.with_count(n)
    options = {}
    if kind == "converged":
        model = DEMDamper(d, integrator="verlet", safety=CONVERGED_SAFETY, cycles=PAPER_CYCLES)
    else:
        model = DEMDamper(d, cycles=PAPER_CYCLES)
        if kind == "refined":
            options["gear_tolerance"] = DEFAULT_GEAR_TOLERANCE / REFINEMENT["gear"][1]
    ps = ParticleSet.lattice(n, d.box, d.particle_radius, d.particle_material)
    if jitter:
        rng = np.random.default_rng(jitter)
        ps = ParticleSet(ps.positions + rng.uniform(-1e-9, 1e-9, ps.positions.shape),
                         d.particle_radius, d.particle_material)
    eng = DEMEngine(ps, Container(d.box, d.wall_material, d.container_mass), model.contact,
                    HarmonicMotion(x_mm * 1e-3, f),
                    EngineSettings(integrator=model.integrator, safety=model.safety, **options))
    c0 = time.thread_time()
    res = eng.run(model.cycles / f, sample_rate=model.sample_rate)
    cpu = time.thread_time() - c0
    cp = res.complex_power(model.skip_cycles)
    return {"eta": cp.loss_factor, "mass": cp.effective_mass_ratio, "cpu": cpu,
            "steps": res.steps, "vimp": res.max_impact_velocity,
            "overlap": res.max_overlap_ratio, "ledger": res.energy_balance_error()}


def _job(args):
    return args, run(*args)


def _dev(a: float, b: float, floor: float = 0.0) -> float:
    return (a - b) / max(abs(b), floor)


def evaluate(points, jobs: int = 1):
    """Run the four runs of every point; one row per point."""
    from pdamper.models.dem import error_bound

    tasks = [(f, x, n, kind, jit) for f, x, n in points for kind in ("default", "converged")
             for jit in (0, 1)] + [(f, x, n, "refined", 0) for f, x, n in points]
    out = {}
    if jobs > 1:
        with ProcessPoolExecutor(jobs) as ex:
            for args, r in ex.map(_job, tasks):
                out[args] = r
    else:
        for t in tasks:
            out[t] = run(*t)
    rows = []
    for f, x, n in points:
        d, dj, c, cj = (out[(f, x, n, kind, jit)] for kind in ("default", "converged")
                        for jit in (0, 1))
        r = out[(f, x, n, "refined", 0)]
        # the model's error estimate of the single default run, against its deviation
        est_eta = error_bound(d["eta"], r["eta"])
        est_mass = error_bound(d["mass"], r["mass"])
        est = max(est_eta / max(abs(d["eta"]), 0.05), est_mass / abs(d["mass"]))
        act = max(abs(_dev(d["eta"], c["eta"], 0.05)), abs(_dev(d["mass"], c["mass"])))
        sens = max(abs(_dev(dj["eta"], d["eta"], 0.05)), abs(_dev(cj["eta"], c["eta"], 0.05)),
                   abs(_dev(dj["mass"], d["mass"])), abs(_dev(cj["mass"], c["mass"])))
        sensitive = sens > TOLERANCE
        if sensitive:  # compare means: single runs are not reproducible to 1 % here
            de, ce = 0.5 * (d["eta"] + dj["eta"]), 0.5 * (c["eta"] + cj["eta"])
            dm, cm = 0.5 * (d["mass"] + dj["mass"]), 0.5 * (c["mass"] + cj["mass"])
        else:
            de, ce, dm, cm = d["eta"], c["eta"], d["mass"], c["mass"]
        dev_eta = _dev(de, ce, 0.05)
        dev_mass = _dev(dm, cm)
        rows.append({"f": f, "X_mm": x, "n": n, "eta_default": de, "eta_converged": ce,
                     "dev_eta": dev_eta, "mass_default": dm, "mass_converged": cm,
                     "dev_mass": dev_mass, "sensitivity": sens, "sensitive": sensitive,
                     "ok": abs(dev_eta) <= TOLERANCE and abs(dev_mass) <= TOLERANCE,
                     "vimp": c["vimp"], "overlap": c["overlap"], "cpu_default": d["cpu"],
                     "cpu_converged": c["cpu"], "steps_default": d["steps"],
                     "ledger_default": d["ledger"], "estimate": est, "single_dev": act,
                     "bounded": act <= est or act <= RESOLUTION,
                     "cpu_refined": r["cpu"]})
    return rows


def print_table(rows) -> None:
    print(f"{'f/Hz':>5} {'X/mm':>5} {'n':>4} | {'eta def':>8} {'eta conv':>8} {'dev':>7} | "
          f"{'m def':>7} {'m conv':>7} {'dev':>7} | {'sens.':>6} {'v_imp':>6} {'ovl%':>5} | "
          f"{'cpu def':>7} {'cpu conv':>8} | {'est.':>6} {'|dev|':>6}  verdict")
    for r in rows:
        verdict = (("ok" if r["ok"] else "OFF") + (" (sensitive: means)" if r["sensitive"] else "")
                   + ("" if r["bounded"] else ", ESTIMATE BELOW |dev|"))
        print(f"{r['f']:>5g} {r['X_mm']:>5g} {r['n']:>4d} | {r['eta_default']:>8.4f} "
              f"{r['eta_converged']:>8.4f} {100 * r['dev_eta']:>+6.2f}% | "
              f"{r['mass_default']:>7.4f} {r['mass_converged']:>7.4f} {100 * r['dev_mass']:>+6.2f}% | "
              f"{100 * r['sensitivity']:>5.1f}% {r['vimp']:>6.2f} {100 * r['overlap']:>5.1f} | "
              f"{r['cpu_default']:>7.2f} {r['cpu_converged']:>8.1f} | "
              f"{100 * r['estimate']:>5.2f}% {100 * r['single_dev']:>5.2f}%  {verdict}")
    regular = [r for r in rows if not r["sensitive"]]
    if regular:
        def err(r):
            return max(abs(r["dev_eta"]), abs(r["dev_mass"]))

        worst = max(regular, key=err)
        typical = float(np.median([err(r) for r in regular]))
        print(f"\nreproducible points: {len(regular)}, all within 1 %: "
              f"{all(r['ok'] for r in regular)}; worst {100 * err(worst):.2f} % at "
              f"{worst['f']:g} Hz / {worst['X_mm']:g} mm / {worst['n']}; median {100 * typical:.2f} %")
    print(f"sensitive points (a 1e-9 m move changes a converged run by > 1 %): "
          f"{sum(r['sensitive'] for r in rows)}")
    held = [r for r in rows if r["bounded"]]
    print(f"error estimate (2 |default - refined|) >= |default - converged| (or both below "
          f"{100 * RESOLUTION:g} %): {len(held)} of {len(rows)} points; estimate <= 1 % at "
          f"{sum(r['estimate'] <= TOLERANCE for r in rows)} points, of which within 1 % of the "
          f"converged run: {sum(r['estimate'] <= TOLERANCE and r['single_dev'] <= TOLERANCE for r in rows)}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="five points only")
    ap.add_argument("--jobs", type=int, default=1, help="processes (default 1)")
    ap.add_argument("--json", help="also write the rows to this JSON file")
    args = ap.parse_args(argv)
    from pdamper.dem import warmup

    warmup()
    rows = evaluate(QUICK if args.quick else GRID, args.jobs)
    print_table(rows)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
