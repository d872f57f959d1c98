"""Is a run from the lattice integrated converged? The paper's protocol (the 4 x 4 lattice
of 32 spheres, every height moved by +-0.02 mm, settling, 8 cycles, cycles 3-8 averaged) on
the 12 points of the LIGGGHTS comparison (5-20 Hz x 10-80 mm), each damping law, at Gear
tolerances (``--tolerance``, default 1e-6, 1e-9 and 1e-10), with Gear's free flights off at
the default (``LATTICE_GEAR_TOLERANCE``), and optionally velocity Verlet (``--verlet
0.005``). The table of docs/agreement.md, "How the lattice is integrated".

    python benchmarks/lattice_convergence.py [--law tsuji --law exact] [--jitter 1 --jitter 2]
        [--tolerance 1e-6 ...] [--verlet 0.005] [--point HZ MM] [--out runs.json]

One thread; CPU seconds per run from ``time.thread_time``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent / "liggghts"))

from agreement import GRID, jittered_lattice  # noqa: E402


def run(f: float, x_mm: float, law: str, positions, **settings) -> dict:
    """One run from ``positions``: loss factor, mass ratio, steps, CPU seconds."""
    from pdamper.dem import HarmonicMotion, ParticleSet
    from pdamper.models import DEMDamper
    from pdamper.parameters import PAPER_DAMPER

    d = PAPER_DAMPER.with_count(32)
    model = DEMDamper(d, cycles=8, damping_model=law, packing="lattice", **settings)
    ps = ParticleSet(positions, d.particle_radius, d.particle_material)
    eng = model._engine(ps, HarmonicMotion(x_mm * 1e-3, f), **model._level2_settling(),
                        **model._transient("lattice"))
    c0 = time.thread_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # fast impacts at 20 Hz / 80 mm: a regime
        res = eng.run(8 / f, sample_rate=model.sample_rate)
    cp = res.complex_power(2)
    return {"eta": cp.loss_factor, "mass": cp.effective_mass_ratio, "steps": int(res.steps),
            "cpu": time.thread_time() - c0}


def main(argv=None) -> None:
    from pdamper.models.dem import LATTICE_GEAR_TOLERANCE

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--law", action="append", choices=["tsuji", "exact", "gonthier"])
    ap.add_argument("--jitter", type=int, action="append", help="jitter seeds (default 1)")
    ap.add_argument("--tolerance", type=float, action="append",
                    help="Gear tolerances (default 1e-6, 1e-9, 1e-10)")
    ap.add_argument("--verlet", type=float, action="append", default=[],
                    help="velocity Verlet at this safety factor too")
    ap.add_argument("--point", type=float, nargs=2, action="append", metavar=("HZ", "MM"))
    ap.add_argument("--out", default=None, help="write the runs as JSON here")
    args = ap.parse_args(argv)
    laws = args.law or ["tsuji", "exact"]
    tols = args.tolerance or [1e-6, LATTICE_GEAR_TOLERANCE, 1e-10]
    points = [tuple(p) for p in args.point] if args.point else GRID
    kinds = [(f"gear {t:g}", {"gear_tolerance": t}) for t in tols]
    kinds.append((f"gear {LATTICE_GEAR_TOLERANCE:g}, no free flights",
                  {"gear_tolerance": LATTICE_GEAR_TOLERANCE, "gear_free_flight": False}))
    kinds += [(f"verlet {s:g}", {"integrator": "verlet", "safety": s}) for s in args.verlet]
    rows = []
    print("eta / m_eff/m_bed (steps) per kind; cycles 3-8 from the jittered lattice")
    print("| law | jitter | point | " + " | ".join(k for k, _ in kinds) + " |")
    print("|---|---|---|" + "---|" * len(kinds))
    for law in laws:
        for jit in args.jitter or [1]:
            pos = jittered_lattice(jit)
            for f, x in points:
                cells = []
                for name, settings in kinds:
                    r = run(f, x, law, pos, **settings)
                    rows.append({"law": law, "jitter": jit, "f": f, "x": x, "kind": name, **r})
                    cells.append(f"{r['eta']:.3f} / {r['mass']:.3f} ({r['steps'] // 1000} k)")
                print(f"| {law} | {jit} | {f:g} Hz / {x:g} mm | " + " | ".join(cells) + " |",
                      flush=True)
                if args.out:
                    Path(args.out).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
