"""Rattling columns or collect-and-collide: the runs behind the table of docs/agreement.md.

``python benchmarks/bench_dem_laws.py`` runs the benchmark damper (32 spheres in the
paper's lattice, constant COR 0.6 / 0.85, mu 0.1, Gear, default settings) at the points
where codes with Tsuji's law find a rattling bed, for long runs, varying one ingredient
at a time: the damping law, the onset-speed floor of the impact-velocity laws, the
re-impact rule, the friction regularisation and a 1e-9 m move of every sphere. It prints
the loss factor over consecutive windows of 6 cycles from cycle 3 (stationarity).
``--liggghts`` adds LIGGGHTS 3.8 runs of the same points (deck in ``benchmarks/liggghts``;
minutes each), with and without its tangential spring.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np

POINTS = [(10.0, 15.0, 38), (14.0, 15.0, 32), (6.0, 15.0, 32), (12.0, 10.0, 32)]
VARIANTS = [
    ("exact (default)", {}),
    ("gonthier", {"damping_model": "gonthier"}),
    ("tsuji", {"damping_model": "tsuji"}),
    ("tsuji, moved 1e-9 m", {"damping_model": "tsuji", "jitter": 1}),
    ("tsuji, v_reg 0.001", {"damping_model": "tsuji", "regularisation_velocity": 1e-3}),
    ("exact, floor 0.001", {"min_impact_velocity": 1e-3}),
    ("exact, floor 0.1", {"min_impact_velocity": 0.1}),
    ("exact, floor 1", {"min_impact_velocity": 1.0}),
    ("exact, re-impact 1.01", {"reimpact_factor": 1.01}),
    ("exact, re-impact 4", {"reimpact_factor": 4.0}),
    ("exact, re-impact off", {"reimpact_factor": 1e9}),
    ("exact, v_reg 0.001", {"regularisation_velocity": 1e-3}),
    ("exact, v_reg 0.1", {"regularisation_velocity": 0.1}),
    ("exact, moved 1e-9 m", {"jitter": 1}),
]


def windows(f: float, x_mm: float, cycles: int, damping_model: str = "exact", jitter: int = 0,
            **contact) -> list[float]:
    """Loss factor over windows of 6 cycles from cycle 3 of one pdamper run."""
    from pdamper.dem import Container, DEMEngine, EngineSettings, HarmonicMotion, ParticleSet
    from pdamper.models import DEMDamper
    from pdamper.parameters import PAPER_DAMPER

    d = PAPER_DAMPER
    model = DEMDamper(d, damping_model=damping_model)
    ps = ParticleSet.lattice(d.count, d.box, d.particle_radius, d.particle_material)
    if jitter:
        rng = np.random.default_rng(jitter)
        ps = ParticleSet(ps.positions + rng.uniform(-1e-9, 1e-9, ps.positions.shape),
                         d.particle_radius, d.particle_material)
    eng = DEMEngine(ps, Container(d.box, d.wall_material, d.container_mass),
                    replace(model.contact, **contact), HarmonicMotion(x_mm * 1e-3, f),
                    EngineSettings(integrator="gear"))
    res = eng.run(cycles / f, sample_rate=4000.0)
    return [res.complex_power(s, 6).loss_factor for s in range(2, cycles - 5, 6)]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--liggghts", action="store_true", help="add LIGGGHTS runs (slow)")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    for f, x, cycles in POINTS:
        print(f"\n{f:g} Hz / {x:g} mm, {cycles} cycles: loss factor per 6-cycle window")
        for name, kw in VARIANTS:
            w = windows(f, x, cycles, **kw)
            print(f"  {name:<24} " + " ".join(f"{v:6.3f}" for v in w), flush=True)
        if args.liggghts:
            sys.path.insert(0, str(Path(__file__).parent / "liggghts"))
            from liggghts_damper import run_liggghts

            for tang in ("history", "no_history"):
                r = run_liggghts(f, x * 1e-3, cycles=cycles, tangential=tang, per_cycle=200)
                print(f"  {'LIGGGHTS ' + tang:<24} " + " ".join(f"{v:6.3f}" for v in r["blocks"]),
                      flush=True)


if __name__ == "__main__":
    main()
