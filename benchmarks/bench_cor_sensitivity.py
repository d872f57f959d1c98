"""COR sensitivity of the paper's damper: DEM Level II points and the Level III
model-1 run under several COR models; prints the tables of docs/restitution.md and writes
its figure. Also times the Level I calibration check (``pdamper cor``) over a grid of pairs.

Run: ``python benchmarks/bench_cor_sensitivity.py [--cycles 48 --skip-cycles 16]
[--figure docs/figures/cor_sensitivity.png]``. About two minutes on one core. Also prints
the loss factor per 4-cycle window at 10 Hz / 15 mm (the initial transient).
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from pdamper.contact.thornton import ThorntonRestitution
from pdamper.dem.impacts import check_restitution
from pdamper.io.scenario import load_scenario
from pdamper.materials import PVC, S235, get_material
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.reports.cor_sensitivity import sensitivity_figure
from pdamper.runs.cor_sensitivity import run_cor_sensitivity


def calibration() -> None:
    """Worst |e_DEM - e| of single impacts over 0.01-3 m/s (60 log-spaced speeds)."""
    v = np.geomspace(0.01, 3.0, 60)
    steel = get_material("100Cr6")
    cases = [("paper steel-steel", paper.PAPER_COR_PP, S235, S235),
             ("paper steel-PVC", paper.PAPER_COR_PW, S235, PVC),
             ("Thornton S235-S235", ThorntonRestitution.from_materials(S235, S235, 0.005, 0.005),
              S235, S235),
             ("Thornton S235-PVC", ThorntonRestitution.from_materials(S235, PVC, 0.005), S235, PVC),
             ("Thornton 100Cr6-100Cr6", ThorntonRestitution.from_materials(
                 steel, steel, 0.005, 0.005), steel, steel),
             ("paper steel-steel x 1.5", paper.PAPER_COR_PP.scaled(1.5), S235, S235)]
    print("Level I: single DEM impacts vs target, 60 speeds in 0.01-3 m/s, r = 5 mm")
    print("| curve | exact, gear | exact, verlet | gonthier, gear | wall s (exact, gear) |")
    print("|---|---|---|---|---|")
    for name, curve, a, b in cases:
        t0 = time.perf_counter()
        g = check_restitution(v, curve, a, b, 0.005).max_deviation
        t = time.perf_counter() - t0
        vv = check_restitution(v, curve, a, b, 0.005, integrator="verlet").max_deviation
        go = check_restitution(v, curve, a, b, 0.005, damping_model="gonthier").max_deviation
        print(f"| {name} | {g:.1e} | {vv:.1e} | {go:.1e} | {t:.2f} |")


def transient() -> None:
    """Loss factor per 4-cycle window, 48 cycles at 10 Hz / 15 mm, three COR models."""
    from pdamper.models import DEMDamper

    print("\nLevel II at 10 Hz / 15 mm, eta per 4-cycle window (cycles 1-4, 5-8, ..., 45-48)")
    for name, pp, pw in (("0.6/0.85", None, None),
                         ("paper", paper.PAPER_COR_PP, paper.PAPER_COR_PW),
                         ("paper*1.5", paper.PAPER_COR_PP.scaled(1.5),
                          paper.PAPER_COR_PW.scaled(1.5))):
        d = paper.PAPER_DAMPER if pp is None else paper.PAPER_DAMPER.with_restitution(pp, pw)
        res = DEMDamper(d, cycles=48, skip_cycles=0).run(10.0, 0.015)
        etas = [res.complex_power(k, 4).loss_factor for k in range(0, 48, 4)]
        print(f"  {name:10s} " + " ".join(f"{e:.2f}" for e in etas))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--cycles", type=int, default=48)
    ap.add_argument("--skip-cycles", type=int, default=16)
    ap.add_argument("--figure", type=Path, default=None)
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} (2-core machine)\n")
    calibration()
    transient()
    sc = load_scenario(None, {"dem.cycles": args.cycles, "dem.skip_cycles": args.skip_cycles})
    t0 = time.perf_counter()
    study = run_cor_sensitivity(sc)
    print(f"\nCOR sensitivity, 32 spheres, {args.cycles} cycles per Level II point "
          f"({time.perf_counter() - t0:.1f} s wall)\n")
    print(study.markdown())
    if args.figure is not None:
        fig = sensitivity_figure(study)
        fig.savefig(args.figure, dpi=100)
        print(f"figure written to {args.figure}")


if __name__ == "__main__":
    main()
