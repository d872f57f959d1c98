"""Large beds: what the settling and the excitation cost by bed size.

The paper's damper box (40 x 40 x 120 mm PVC, steel spheres, COR 0.6 / 0.85, mu 0.1)
filled with the same bed mass in smaller spheres: 32 x 5 mm, 250 x 2.5 mm and (``--large``)
1 200 x 1.5 mm, random beds, 10 Hz / 32 mm, the DEM damper's Level II protocol (Gear,
settling, then ``--cycles`` cycles, the last ``cycles - 2`` averaged). Each bed is settled
twice: for the whole settling time (free fall + 1 s, the default) and with the rest rule
(``settle_rest_speed``, ``--rest-speed``, 1 mm/s by default here: the settling ends once
the bed's rms speed has stayed below it for 0.05 s). Per bed and settling, one line: the
settling's bed time, steps, CPU seconds and ns per particle-step, the excitation's the
same, the loss factor and the effective mass ratio, the settled bed's height and mean
coordination number.

CPU seconds are the process's (``time.process_time``), which a shared machine's load does
not inflate much. LIGGGHTS (``benchmarks/liggghts``) runs beside it only where the
``liggghts`` executable is installed, and only for the 32- and 250-sphere beds.

Run::

    python3 benchmarks/bench_large_beds.py                   # 32 and 250 spheres, seed 0
    python3 benchmarks/bench_large_beds.py --seeds 0,1,2 --cycles 8
    python3 benchmarks/bench_large_beds.py --large            # and 1 200 x 1.5 mm (long)
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

#: (spheres, radius [m]): the same bed mass as the paper's 32 x 5 mm.
BEDS = ((32, 0.005), (250, 0.0025))
LARGE = ((1200, 0.0015),)
#: The two settlings compared: the whole settling time, and the rest rule.
SETTLINGS = {"whole": {}, "rest": {"settle_rest_speed": 1e-3}}


def bed_statistics(bed) -> tuple[float, float]:
    """Height of the settled bed above the floor [m] and its mean coordination number
    (sphere-sphere contacts per sphere)."""
    p = bed.state.pos
    r = np.asarray(bed.state.part.rad)
    z = p[:, 2] - bed.state.z_start
    d = np.linalg.norm(p[:, None] - p[None], axis=2)
    touch = d < (r[:, None] + r[None]) * (1 + 1e-6)
    np.fill_diagonal(touch, False)
    return float(np.max(z + r)), float(touch.sum() / len(p))


def measure(count: int, radius: float, seed: int, cycles: int, settling: dict) -> dict:
    """One bed settled and shaken: the row's figures."""
    from pdamper.models.dem import DEMDamper
    from pdamper.parameters import PAPER_DAMPER

    damper = dataclasses.replace(PAPER_DAMPER, count=count, particle_radius=radius)
    model = DEMDamper(damper, packing="random", seed=seed, cycles=cycles, skip_cycles=2,
                      **settling)
    _, _, engine = model._point_engine(10.0, 0.032)
    t0 = time.process_time()
    bed = model._settled(engine)  # the bed the run starts from (the model's memo)
    settle_cpu = time.process_time() - t0
    t0 = time.process_time()
    run = model.steady_run(10.0, 0.032)
    cpu = time.process_time() - t0
    height, coordination = bed_statistics(bed)
    return dict(settle_time=bed.simulated, stop=bed.stop, settle_steps=bed.steps,
                settle_cpu=settle_cpu, steps=run.result.steps, cpu=cpu,
                eta=run.power.loss_factor, mass=run.power.effective_mass_ratio,
                height=height, coordination=coordination)


def liggghts_row(count: int, radius: float, cycles: int, seed: int) -> str:
    """LIGGGHTS at the same point, where it is installed (the existing harness)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parent / "liggghts"))
    import liggghts_damper as lig

    if not lig.available():
        return "LIGGGHTS: not installed here (apt-get install liggghts), not run"
    if radius != 0.005:
        return ("LIGGGHTS: the harness's deck has the paper's radius (5 mm); not run for "
                f"{count} x {1e3 * radius:g} mm")
    t0 = time.perf_counter()
    res = lig.run_liggghts(10.0, 0.032, count=count, cycles=cycles, insert_seed=seed)
    keys = ", ".join(f"{k} {v:.4g}" for k, v in res.items() if isinstance(v, float))
    return f"LIGGGHTS (random insertion, seed {seed}; {time.perf_counter() - t0:.1f} s wall): {keys}"


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="0", help="random beds' seeds, comma-separated")
    ap.add_argument("--cycles", type=int, default=4, help="cycles of the excitation")
    ap.add_argument("--large", action="store_true", help="add 1 200 x 1.5 mm (long)")
    ap.add_argument("--liggghts", action="store_true", help="run LIGGGHTS beside it")
    ap.add_argument("--rest-speed", type=float, default=1e-3,
                    help="settle_rest_speed of the rest rule [m/s] (default 1e-3)")
    ap.add_argument("--only", type=int, action="append",
                    help="only the bed of this many spheres (repeatable)")
    args = ap.parse_args(argv)
    from pdamper.dem.simulation import warmup

    warmup(("gear",), ("harmonic",))
    print(f"10 Hz / 32 mm, random beds, Gear, settle + {args.cycles} cycles; CPU seconds")
    print(f"{'bed':>14} {'seed':>4} {'settling':>8} {'bed time':>8} {'stop':>7} "
          f"{'steps':>9} {'CPU s':>7} {'ns/p-step':>9} | {'steps':>9} {'CPU s':>7} "
          f"{'ns/p-step':>9} | {'eta':>6} {'m_eff':>6} {'h [mm]':>6} {'Z':>5}")
    for count, radius in BEDS + (LARGE if args.large else ()):
        if args.only and count not in args.only:
            continue
        for seed in (int(s) for s in args.seeds.split(",")):
            for name, settling in SETTLINGS.items():
                if "settle_rest_speed" in settling:
                    settling = {**settling, "settle_rest_speed": args.rest_speed}
                m = measure(count, radius, seed, args.cycles, settling)
                ns_settle = 1e9 * m["settle_cpu"] / max(1, m["settle_steps"] * count)
                ns = 1e9 * m["cpu"] / max(1, m["steps"] * count)
                print(f"{count:>5} x {1e3 * radius:3.1f} mm {seed:>4} {name:>8} "
                      f"{m['settle_time']:>7.3f}s {m['stop']:>7} {m['settle_steps']:>9d} "
                      f"{m['settle_cpu']:>7.2f} {ns_settle:>9.1f} | {m['steps']:>9d} "
                      f"{m['cpu']:>7.2f} {ns:>9.1f} | {m['eta']:>6.3f} {m['mass']:>6.3f} "
                      f"{1e3 * m['height']:>6.2f} {m['coordination']:>5.2f}", flush=True)
            if args.liggghts and count in (32, 250):
                print("   ", liggghts_row(count, radius, args.cycles, seed), flush=True)


if __name__ == "__main__":
    main()
