"""Level III wall times: each damper model on the paper's 2 s free vibration (Figs. 7/8),
over particle counts from few to many, the N-mode coupling, and a design study.

Run: ``python benchmarks/bench_level3.py [--dem-map FILE.nc] [--repeat N]``

Models: 3 (analytical), 2 (effective fields, from the paper's 14 x 24 analytical map, a
fine map around the trajectory, and a DEM map if one is given) and 1 (DEM co-simulation,
Gear and Verlet). Times are best of N after one warm-up run; the DEM's start-up (numba
cache load or compile, on a 10 ms run) is reported separately.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from pdamper.analysis.fields import effective_field
from pdamper.coupling import Simulation
from pdamper.design import optimize_design
from pdamper.models import AnalyticalDamper, DEMDamper, EffectiveFieldDamper
from pdamper.parameters import (
    PAPER_DAMPER,
    PAPER_INITIAL_DISPLACEMENT,
    PAPER_STRUCTURE,
    paper_beam,
)
from pdamper.structure.beam import modal_reduction
from pdamper.structure.modal import ModalStructure

DURATION = 2.0


def best_of(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def run(structure, model):
    return Simulation(structure, model, PAPER_INITIAL_DISPLACEMENT).run(DURATION)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dem-map", help="NetCDF DEM map of the 32-sphere damper for model 2")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--dem-repeat", type=int, default=1)
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; best of "
          f"{args.repeat}; {DURATION:g} s of free vibration from -58 mm")
    s = PAPER_STRUCTURE
    print("\nmodel                                  particles   wall [s]   A(0.75 s) [mm]")
    rows = []
    for n in (16, 32, 64, 128, 176):
        d = PAPER_DAMPER.with_count(n)
        m3 = AnalyticalDamper(d)
        run(s, m3)
        t, r = best_of(lambda m3=m3: run(s, m3), args.repeat)
        rows.append(("model 3, analytical", n, t, r.amplitude_at(0.75)))
        ana_map = effective_field(m3, np.linspace(2, 20, 14), np.linspace(0.001, 0.2, 24))
        m2 = EffectiveFieldDamper(d, field=ana_map, extrapolation="clamp")
        run(s, m2)
        t, r = best_of(lambda m2=m2: run(s, m2), args.repeat)
        rows.append(("model 2, fields (analytical 14 x 24)", n, t, r.amplitude_at(0.75)))
    fine = effective_field(AnalyticalDamper(PAPER_DAMPER), np.linspace(4.5, 6, 13),
                           np.linspace(0.005, 0.065, 121))
    m2 = EffectiveFieldDamper(PAPER_DAMPER, field=fine)
    t, r = best_of(lambda: run(s, m2), args.repeat)
    rows.append(("model 2, fields (analytical 13 x 121)", 32, t, r.amplitude_at(0.75)))
    if args.dem_map:
        m2 = EffectiveFieldDamper(PAPER_DAMPER, args.dem_map, extrapolation="clamp")
        t, r = best_of(lambda: run(s, m2), args.repeat)
        rows.append(("model 2, fields (DEM map)", 32, t, r.amplitude_at(0.75)))
    for integrator, counts in (("gear", (32, 176)), ("auto", (32, 176)), ("verlet", (32,))):
        for n in counts:
            m1 = DEMDamper(PAPER_DAMPER.with_count(n), integrator=integrator)
            t0 = time.perf_counter()  # a short run: compile or load the numba cache
            Simulation(s, m1, PAPER_INITIAL_DISPLACEMENT).run(0.01)
            first = time.perf_counter() - t0
            t, r = best_of(lambda m1=m1: run(s, m1), args.dem_repeat)
            rows.append((f"model 1, DEM {integrator} (start-up {first:.1f} s)", n, t,
                         r.amplitude_at(0.75)))
    for name, n, t, a in rows:
        print(f"{name:40s} {n:6d}   {t:9.4f}   {a * 1e3:10.2f}")

    print("\nN-mode pseudo force (paper beam, damper at the tip, model 3, 32 spheres)")
    beam, tip = paper_beam()
    zeta = modal_reduction(beam, tip).to_structure(0.55).damping_ratio
    m3 = AnalyticalDamper(PAPER_DAMPER)
    for modes in (1, 2, 3, 4, 6):
        ms = ModalStructure.from_beam(beam, tip, modes, damping_ratio=zeta)
        t, r = best_of(lambda ms=ms: run(ms, m3), args.repeat)
        print(f"  {modes} mode(s): {t:8.4f} s   A(0.75 s) = {r.amplitude_at(0.75) * 1e3:.3f} mm")

    print("\ndesign study, model 3, particles=16:176:16 x radius=3mm:6mm:4 (44 designs)")
    specs = ["particles=16:176:16", "radius=3mm:6mm:4"]
    t, res = best_of(lambda: optimize_design(s, PAPER_DAMPER, -0.058, specs), args.repeat)
    print(f"  in-process: {t:.3f} s, best {res.best.particles} spheres of "
          f"{res.best.design['radius'] * 1e3:.1f} mm")
    t, _ = best_of(lambda: optimize_design(s, PAPER_DAMPER, -0.058, specs, workers=2), 1)
    print(f"  dask, 2 worker processes (cluster start included): {t:.3f} s")
    t, res = best_of(lambda: optimize_design(s, PAPER_DAMPER, -0.058,
                                             ["particles=16:176:16", "radius=3mm:6mm"],
                                             method="optimize", max_evaluations=200), 1)
    print(f"  differential evolution, continuous radius, {len(res.candidates)} evaluations: "
          f"{t:.3f} s, best {res.best.particles} spheres of "
          f"{res.best.design['radius'] * 1e3:.2f} mm")


if __name__ == "__main__":
    main()
