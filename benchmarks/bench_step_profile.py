"""Where a DEM run's steps go within the excitation cycle, over the design map.

Run ``python benchmarks/bench_step_profile.py`` (``--quick``: three points; ``--detail``:
the phase table of every point). For each kind of point (the paper's damper as a map runs
it: random packing, Gear, 8 cycles after settling; the full container with ``auto``) it
runs the excitation with ``step_profile=True``, bins the steps of cycles 3-8 over the cycle
(:meth:`pdamper.dem.DEMResult.step_profile`, 20 bins) and prints

* Gear's steps per cycle and its mean step against the velocity-Verlet step of the point
  (the step of the LIGGGHTS comparison, ``benchmarks/liggghts/compare.py``);
* the *sphere-step gain*: velocity Verlet's sphere-steps over a cycle (all spheres, every
  step) over Gear's (the spheres each step integrated, free flights left out): how much
  integration the variable step and the free flights save, over the whole cycle and over
  the *impact-bound* bins (Gear's mean step below twice Verlet's: impacts and a pressed
  bed, where every explicit step is held by the contacts);
* the share of the steps and of the integrator's wall time in those bins.

A Gear sphere-step costs about 2.4 Verlet sphere-steps (docs/dem.md, Integrators), so a
gain below ~2.4 in a bin means Gear is no cheaper there than velocity Verlet would be.
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

from pdamper.dem import HarmonicMotion, warmup
from pdamper.models import DEMDamper
from pdamper.parameters import PAPER_DAMPER

#: (label, frequency [Hz], amplitude [m], spheres, packing, integrator, cycles)
POINTS = [
    ("slow corner", 2.0, 0.2, 32, "random", "gear", 8),
    ("fast corner", 20.0, 0.2, 32, "random", "gear", 8),
    ("small stroke", 20.0, 0.001, 32, "random", "gear", 8),
    ("tuned point", 10.0, 0.032, 32, "random", "gear", 8),
    ("rattling", 10.0, 0.015, 32, "random", "gear", 8),
    ("mid map", 5.0, 0.05, 32, "random", "gear", 8),
    ("96 spheres", 10.0, 0.032, 96, "random", "gear", 8),
    ("full container", 20.0, 0.032, 192, "lattice", "auto", 4),
]
QUICK = ("fast corner", "tuned point", "slow corner")
BINS = 20
#: a bin is impact-bound when Gear's mean step there is below this many Verlet steps
IMPACT_BOUND = 2.0


def profile(f, x, n, packing, integrator, cycles):
    model = DEMDamper(dataclasses.replace(PAPER_DAMPER, count=n), packing=packing,
                      integrator=integrator, cycles=cycles)
    engine = model.build_engine(HarmonicMotion(x, f))
    bed = engine.settle()
    c0 = time.process_time()
    res = engine.run(cycles / f, sample_rate=model.sample_rate, start=bed, step_profile=True)
    cpu = time.process_time() - c0
    skip = min(2, cycles - 1)
    return res, res.step_profile(BINS, skip_cycles=skip), cpu, engine.time_step


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--detail", action="store_true", help="print each point's phase table")
    args = ap.parse_args()
    warmup()
    print(f"Steps over the cycle ({BINS} phase bins, cycles 3-8; impact-bound bins: Gear's "
          f"mean step < {IMPACT_BOUND:g} x Verlet's)")
    print(f"{'point':<15} {'f':>4} {'X mm':>5} {'n':>4} {'CPU s':>6} {'steps/cyc':>9} "
          f"{'Gear dt us':>10} {'Verlet dt':>9} {'gain':>5} | {'bound bins':>10} "
          f"{'steps %':>7} {'wall %':>6} {'stepped':>7} {'gain':>5}")
    for label, f, x, n, packing, integrator, cycles in POINTS:
        if args.quick and label not in QUICK:
            continue
        res, p, cpu, dt_verlet = profile(f, x, n, packing, integrator, cycles)
        period = 1.0 / f
        steps = p["steps"].values                       # per cycle, per bin
        stepped = p["stepped_spheres"].values * steps   # sphere-steps per cycle, per bin
        verlet = n * (period / BINS) / dt_verlet        # Verlet sphere-steps per bin
        bound = p["mean_step"].values < IMPACT_BOUND * dt_verlet
        gain = verlet * BINS / max(np.nansum(stepped), 1.0)
        gain_b = verlet * bound.sum() / max(np.nansum(stepped[bound]), 1.0)
        share_b = p["step_share"].values[bound].sum()
        wall_b = p["wall_share"].values[bound].sum()
        per_b = (np.nansum(stepped[bound]) / max(steps[bound].sum(), 1.0)) if bound.any() else 0
        print(f"{label:<15} {f:>4g} {1e3 * x:>5g} {n:>4d} {cpu:>6.2f} {steps.sum():>9.0f} "
              f"{1e6 * period / max(steps.sum(), 1):>10.3f} {1e6 * dt_verlet:>9.3f} "
              f"{gain:>5.1f} | {bound.sum():>4d} of {BINS:<3d} {100 * share_b:>7.1f} "
              f"{100 * wall_b:>6.1f} {per_b:>7.1f} {gain_b:>5.1f}", flush=True)
        if args.detail:
            print(f"  {'phase':>5} {'steps %':>7} {'wall %':>6} {'dt us':>7} {'stepped':>7} "
                  f"{'rejected':>8} {'a_c m/s2':>9}")
            for k in range(BINS):
                print(f"  {p['phase'].values[k]:>5.3f} {100 * p['step_share'].values[k]:>7.1f} "
                      f"{100 * p['wall_share'].values[k]:>6.1f} "
                      f"{1e6 * p['mean_step'].values[k]:>7.3f} "
                      f"{p['stepped_spheres'].values[k]:>7.1f} {p['rejected'].values[k]:>8.1f} "
                      f"{p['container_acceleration'].values[k]:>9.0f}")


if __name__ == "__main__":
    main()
