"""Evidence for the steady-state criterion (docs/fields.md): long DEM runs of the paper's
damper, their cycle loss factors, and where the criterion stops.

Run ``python benchmarks/bench_stationarity.py`` (``--cycles 60``, ``--points`` to choose;
``--windows 3x4,3x3,2x4,2x3 --cycles 40`` compares window lengths instead, the table of
docs/fields.md).
For every point and both packings (the paper's lattice, a random one) it runs ``--cycles``
cycles once and prints

* eta over cycles 3-8 (the paper's procedure) and whether that window is steady;
* the cycle at which a run until steady stops (:meth:`pdamper.models.DEMDamper.assess` on
  the run cut after each cycle: exactly what ``cycles = "auto"`` does), its window, eta and
  standard error, and the motion mode;
* the mean eta over the last 20 cycles, the reference the stopped value should meet;
* the cycle at which the lattice's mirror symmetry breaks (horizontal force > 1e-5 x
  vertical).
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

#: Points of the window comparison (docs/fields.md): spread over the map, with the drifting
#: scattering and subharmonic beds.
WINDOW_POINTS = ((2, 50), (2, 200), (3.4, 100), (5, 15), (5, 100), (6, 15), (8, 50), (10, 15),
                 (10, 32), (12, 30), (14, 15), (14.5, 100), (18, 20), (20, 5), (20, 50),
                 (20, 200))
POINTS = ((4, 15), (6, 15), (10, 15), (14, 15), (18, 20), (10, 32), (12, 30), (8, 50),
          (5, 100), (3, 200), (20, 5))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=60)
    ap.add_argument("--points", default=None,
                    help="'f/X_mm,...', e.g. '10/15,14/15,18/20' (default: 11 points)")
    ap.add_argument("--windows", default=None,
                    help="compare criteria instead, e.g. '3x4,3x3,2x4,2x3' (windows x cycles; "
                         "random beds, eta at the stop against the mean of the last 20 cycles)")
    args = ap.parse_args(argv)
    if args.windows:
        pts = WINDOW_POINTS if args.points is None else tuple(
            tuple(float(v) for v in p.split("/")) for p in args.points.split(","))
        compare_windows(pts, args.cycles, args.windows)
        return
    from pdamper.analysis.stationarity import SYMMETRY_TOLERANCE, cycle_loss_factors, cycle_symmetry
    from pdamper.models import DEMDamper
    from pdamper.models.dem import truncate_result
    from pdamper.parameters import PAPER_DAMPER

    pts = POINTS if args.points is None else tuple(
        tuple(float(v) for v in p.split("/")) for p in args.points.split(","))
    n = args.cycles
    print(f"{'point':>12} {'packing':>8} | {'eta 3-8':>7} {'steady?':>7} | {'stop':>4} "
          f"{'window':>7} {'eta':>6} {'+-':>5} {'mode':>24} | {'eta last 20':>11} | "
          f"{'symmetry breaks':>15}")
    for f, x_mm in pts:
        for packing in ("lattice", "random"):
            model = DEMDamper(PAPER_DAMPER, packing=packing, seed=1, cycles=n, skip_cycles=2)
            res = model.run(f, x_mm / 1e3)
            auto = DEMDamper(PAPER_DAMPER, packing=packing, seed=1, max_cycles=n)
            eight = DEMDamper(PAPER_DAMPER, packing=packing, seed=1, cycles=8)
            st8, _ = eight.assess(truncate_result(res, 8))
            eta = cycle_loss_factors(res.time, -res.force[:, 2], res.container_velocity, f,
                                     res.bed_mass)
            sym = cycle_symmetry(res.time, res.force, f)
            broken = np.flatnonzero(sym >= SYMMETRY_TOLERANCE)
            brk = f"cycle {broken[0] + 1}" if broken.size else "never"
            stop = None
            for k in range(auto.steady.min_cycles, n + 1):
                st, mo = auto.assess(res if k == n else truncate_result(res, k))
                if st.stationary:
                    stop = (k, st, mo)
                    break
            late = float(np.mean(eta[-20:]))
            if stop is None:
                st, mo = auto.assess(res)
                s_txt = f"{'-':>4} {'not steady: ' + st.reason:>45}"
            else:
                k, st, mo = stop
                s_txt = (f"{k:4d} {st.first_cycle:3d}-{st.last_cycle:<3d} {st.loss_factor:6.3f} "
                         f"{st.stderr:5.3f} {mo.mode.label:>24}")
            print(f"{f:5g} Hz {x_mm:3g} mm {packing:>8} | {st8.loss_factor:7.3f} "
                  f"{'yes' if st8.stationary else 'no':>7} | {s_txt} | {late:11.3f} | "
                  f"{brk:>15}", flush=True)


def compare_windows(points, n: int, spec: str) -> None:
    """For each point one random-bed run of ``n`` cycles; for each criterion of ``spec``
    (``"3x4,2x4"``: windows x cycles per window) the cycle where a run until steady would
    stop and its loss factor against the mean of the last 20 cycles; then a summary."""
    from pdamper.analysis.stationarity import cycle_loss_factors
    from pdamper.models import DEMDamper
    from pdamper.models.dem import truncate_result
    from pdamper.parameters import PAPER_DAMPER

    variants = [tuple(int(v) for v in w.split("x")) for w in spec.split(",")]
    devs: dict = {w: [] for w in variants}
    stops: dict = {w: [] for w in variants}
    for f, x_mm in points:
        res = DEMDamper(PAPER_DAMPER, packing="random", cycles=n).run(f, x_mm / 1e3)
        eta = cycle_loss_factors(res.time, -res.force[:, 2], res.container_velocity, f,
                                 res.bed_mass)
        late = float(np.mean(eta[-20:]))
        cells = []
        for k, m in variants:
            auto = DEMDamper(PAPER_DAMPER, packing="random", max_cycles=n, window_cycles=m,
                             steady_windows=k)
            for c in range(auto.steady.min_cycles, n + 1):
                st, _ = auto.assess(res if c == n else truncate_result(res, c))
                if st.stationary:
                    dev = (st.loss_factor - late) / max(abs(late), 0.05)
                    devs[(k, m)].append(abs(dev))
                    stops[(k, m)].append(c)
                    cells.append(f"{k}x{m}: {c:2d} {st.loss_factor:.3f} ({100 * dev:+.1f} %)")
                    break
            else:
                cells.append(f"{k}x{m}: not steady")
        print(f"{f:5g} Hz {x_mm:5.1f} mm  last 20: {late:.3f} | " + " | ".join(cells),
              flush=True)
    for (k, m), d in devs.items():
        d = np.asarray(d)
        print(f"{k} x {m}: stops at {np.median(stops[(k, m)]):.0f} (median), within 1 / 5 / "
              f"10 %: {(d <= 0.01).sum()} / {(d <= 0.05).sum()} / {(d <= 0.1).sum()} of "
              f"{len(points)}, worst {100 * d.max():.0f} %")


if __name__ == "__main__":
    main(sys.argv[1:])
