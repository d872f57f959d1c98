"""The checks behind the Yade columns of docs/agreement.md: ``python benchmarks/yade/checks.py``.

* **COR**: one normal impact in Yade (a steel sphere on the PVC floor, COR 0.85; two steel
  spheres head-on, COR 0.6) at 0.1 and 1 m/s, no gravity, no friction, at Yade's step of
  the damper runs (0.5 ``PWaveTimeStep()``) and at 0.2, against the target and pdamper's
  Tsuji law (``simulate_impact(..., damping_model="tsuji")``).
* ``--step HZ MM`` (repeatable): the lattice run of jitter 1 at the point with Yade's
  step at 0.5 and 0.2 ``PWaveTimeStep()``, and with ``--stock-wall`` also Yade's stock
  wall stiffness (the PVC's 3 GPa, R* = r / 2: see ``yade_damper``), and with
  ``--liggghts`` LIGGGHTS from the same jitter at its 1 us and at Yade's step.
* ``--same-step HZ MM`` (repeatable): LIGGGHTS from jitters 1 and 2 at Yade's step (the
  table's Yade runs are at that step, its LIGGGHTS runs at 1 us); with ``--fraction F``
  both codes at F ``PWaveTimeStep()``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "liggghts"))

import yade_damper  # noqa: E402


def cor_table() -> None:
    from pdamper.contact.restitution import ConstantRestitution
    from pdamper.dem.impacts import simulate_impact
    from pdamper.parameters import PAPER_DAMPER as d

    print(f"{'pair':<18} {'v m/s':>6} {'target':>7} {'Yade 0.5':>9} {'Yade 0.2':>9} "
          f"{'pdamper tsuji':>13}")
    for pair, e in (("wall", 0.85), ("sphere", 0.6)):
        for v in (0.1, 1.0):
            y5 = yade_damper.impact_cor(pair, v, e)
            y2 = yade_damper.impact_cor(pair, v, e, step_fraction=0.2)
            pd = simulate_impact(v, ConstantRestitution(e), d.particle_material,
                                 d.wall_material, d.particle_radius, pair == "sphere",
                                 damping_model="tsuji")
            name = "sphere-wall" if pair == "wall" else "sphere-sphere"
            print(f"{name:<18} {v:>6g} {e:>7.3f} {y5:>9.5f} {y2:>9.5f} {pd:>13.5f}", flush=True)


def step_check(f: float, x: float, stock: bool, liggghts: bool) -> None:
    import agreement
    from liggghts_damper import run_liggghts

    pos = agreement.jittered_lattice(1)
    runs = [("0.5 PWave", {}), ("0.2 PWave", {"step_fraction": 0.2})]
    if stock:
        runs.append(("stock wall", {"wall": "yade"}))
    for name, kw in runs:
        r = yade_damper.run_yade(f, x * 1e-3, positions=pos, **kw)
        print(f"{f:g} Hz / {x:g} mm, {name:<10} (dt {r['dt'] * 1e6:.3f} us): eta "
              f"{r['loss_factor']:.4f} m_eff/m_bed {r['effective_mass_ratio']:.4f} "
              f"({r['cpu']:.0f} s CPU)", flush=True)
    for dt in (agreement.LIGGGHTS_STEP, r["dt"]) if liggghts else ():
        lg = run_liggghts(f, x * 1e-3, dt=dt, cycles=agreement.LATTICE_CYCLES,
                          skip_cycles=agreement.LATTICE_SKIP, positions=pos)
        print(f"{f:g} Hz / {x:g} mm, LIGGGHTS   (dt {lg['dt'] * 1e6:.3f} us): eta "
              f"{lg['loss_factor']:.4f} m_eff/m_bed {lg['effective_mass_ratio']:.4f} "
              f"({lg['cpu']:.0f} s CPU)", flush=True)


def same_step(f: float, x: float, fraction: float) -> None:
    import agreement
    from liggghts_damper import run_liggghts

    dt = yade_damper.step(f, step_fraction=fraction)[0]
    for k in (1, 2):
        pos = agreement.jittered_lattice(k)
        lg = run_liggghts(f, x * 1e-3, dt=dt, cycles=agreement.LATTICE_CYCLES,
                          skip_cycles=agreement.LATTICE_SKIP, positions=pos)
        print(f"{f:g} Hz / {x:g} mm, jitter {k}, LIGGGHTS (dt {lg['dt'] * 1e6:.3f} us): eta "
              f"{lg['loss_factor']:.4f} m_eff/m_bed {lg['effective_mass_ratio']:.4f} "
              f"({lg['cpu']:.0f} s CPU)", flush=True)
        if fraction != yade_damper.STEP_FRACTION:
            y = yade_damper.run_yade(f, x * 1e-3, positions=pos, step_fraction=fraction)
            print(f"{f:g} Hz / {x:g} mm, jitter {k}, Yade     (dt {y['dt'] * 1e6:.3f} us): "
                  f"eta {y['loss_factor']:.4f} m_eff/m_bed {y['effective_mass_ratio']:.4f} "
                  f"({y['cpu']:.0f} s CPU)", flush=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--step", type=float, nargs=2, action="append", metavar=("HZ", "MM"),
                    help="the step check at this point (repeatable)")
    ap.add_argument("--stock-wall", action="store_true",
                    help="--step: also Yade's stock wall stiffness")
    ap.add_argument("--liggghts", action="store_true",
                    help="--step: also LIGGGHTS at its 1 us and at Yade's step")
    ap.add_argument("--same-step", type=float, nargs=2, action="append", metavar=("HZ", "MM"),
                    help="LIGGGHTS at Yade's step at this point, jitters 1 and 2 (repeatable)")
    ap.add_argument("--fraction", type=float, default=yade_damper.STEP_FRACTION,
                    help="--same-step: the step as a fraction of PWaveTimeStep (other than "
                    "the table's 0.5: Yade runs at it too)")
    args = ap.parse_args(argv)
    if not yade_damper.available():
        sys.exit("yade not found (Debian: apt-get install yade)")
    for f, x in args.same_step or ():
        same_step(f, x, args.fraction)
    if args.step:
        for f, x in args.step:
            step_check(f, x, args.stock_wall, args.liggghts)
    elif not args.same_step:
        cor_table()


if __name__ == "__main__":
    main()
