"""Evidence for the steady-state criterion (docs/fields.md): long DEM runs of the paper's
damper, their cycle loss factors, and where the criterion stops.

Run ``python benchmarks/bench_stationarity.py`` (``--cycles 60``, ``--points`` to choose;
``--windows 3x4,3x3,2x4,2x3 --cycles 40`` compares window lengths instead, the table of
docs/fields.md; a window ``3x4q2`` is three windows of 4 cycles with the rule for quiet
beds on windows of 2, ``3x4q2w3s2`` on three of them after two skipped cycles (the earlier
rule, kept for comparison), ``3x4q0`` without it, plain ``3x4`` the model's default quiet rule;
``--points grid`` the 9 x 5 points of its table, ``--particles N``, ``--jobs 2``).
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
#: The rule for quiet beds (docs/fields.md): 9 frequencies of the paper's 14 x 5 strokes of
#: its 24, from the solid-like cells to the fast corner.
GRID_POINTS = tuple((f, x) for f in (2.0, 3.385, 4.769, 6.154, 8.923, 11.69, 14.46, 17.23, 20.0)
                    for x in (9.65, 35.7, 70.3, 122.0, 200.0))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=60)
    ap.add_argument("--points", default=None,
                    help="'f/X_mm,...', e.g. '10/15,14/15,18/20' (default: 11 points)")
    ap.add_argument("--windows", default=None,
                    help="compare criteria instead, e.g. '3x4q0,3x4q2,2x4' (windows x cycles, "
                         "qN: quiet windows of N cycles, q0: none; random beds, eta at the "
                         "stop against the mean of the last 20 cycles)")
    ap.add_argument("--particles", type=int, default=32, help="spheres (window comparison)")
    ap.add_argument("--jobs", type=int, default=1, help="processes (window comparison)")
    ap.add_argument("--seed", type=int, default=0,
                    help="seed of the random packing (window comparison; default 0)")
    args = ap.parse_args(argv)
    if args.windows:
        if args.points == "grid":
            pts = GRID_POINTS
        elif args.points is None:
            pts = WINDOW_POINTS
        else:
            pts = tuple(tuple(float(v) for v in p.split("/")) for p in args.points.split(","))
        compare_windows(pts, args.cycles, args.windows, args.particles, args.jobs, args.seed)
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


def _variant(spec: str) -> tuple[int, int, dict | None]:
    """``"3x4"`` -> (3, 4, None: the default quiet rule); ``"3x4q2"`` -> (3, 4, quiet
    windows of 2 cycles); ``"3x4q2w3s2"``: three of them after two cycles (the earlier
    rule, kept for comparison)."""
    body, _, quiet = spec.partition("q")
    k, m = (int(v) for v in body.split("x"))
    if not quiet:
        return k, m, None
    rest, _, skip = quiet.partition("s")
    cycles, _, windows = rest.partition("w")
    opts = {"quiet_window_cycles": int(cycles)}
    if windows:
        opts["quiet_windows"] = int(windows)
    if skip:
        opts["quiet_skip_cycles"] = int(skip)
    return k, m, opts


def _long_run(args):
    """One random-bed run of ``n`` cycles at (f, X); the stops of every criterion."""
    import warnings

    from pdamper.analysis.stationarity import cycle_loss_factors
    from pdamper.models import DEMDamper
    from pdamper.models.dem import truncate_result
    from pdamper.parameters import PAPER_DAMPER

    (f, x_mm), n, variants, count, seed = args
    warnings.simplefilter("ignore")
    damper = PAPER_DAMPER.with_count(count)
    res = DEMDamper(damper, packing="random", seed=seed, cycles=n).run(f, x_mm / 1e3)
    eta = cycle_loss_factors(res.time, -res.force[:, 2], res.container_velocity, f,
                             res.bed_mass)
    late = float(np.mean(eta[-20:]))
    stops = []
    for k, m, q in variants:
        quiet = {} if q is None else q
        auto = DEMDamper(damper, packing="random", seed=seed, max_cycles=n, window_cycles=m,
                         steady_windows=k, **quiet)
        for c in range(auto.steady.min_cycles, n + 1):
            st, mo = auto.assess(res if c == n else truncate_result(res, c))
            if st.stationary:
                stops.append((c, st.loss_factor, st.quiet, mo.mode.label))
                break
        else:
            stops.append(None)
    return (f, x_mm), late, float(np.std(eta[-20:], ddof=1)), stops


def compare_windows(points, n: int, spec: str, count: int = 32, jobs: int = 1,
                    seed: int = 0) -> None:
    """For each point one random-bed run of ``n`` cycles; for each criterion of ``spec``
    (``"3x4q0,3x4q2"``: windows x cycles per window, quiet windows) the cycle where a run
    until steady would stop and its loss factor against the mean of the last 20 cycles;
    then a summary."""
    from concurrent.futures import ProcessPoolExecutor

    specs = spec.split(",")
    variants = [_variant(w) for w in specs]
    devs: dict = {w: [] for w in specs}
    stops: dict = {w: [] for w in specs}
    quiet_devs: dict = {w: [] for w in specs}
    tasks = [(p, n, variants, count, seed) for p in points]
    with ProcessPoolExecutor(jobs) as ex:
        for (f, x_mm), late, sd, found in ex.map(_long_run, tasks):
            cells = []
            for w, stop in zip(specs, found, strict=True):
                if stop is None:
                    cells.append(f"{w}: not steady")
                    continue
                c, value, quiet, mode = stop
                dev = (value - late) / max(abs(late), 0.05)
                devs[w].append(abs(dev))
                stops[w].append(c)
                if quiet:
                    quiet_devs[w].append(abs(dev))
                cells.append(f"{w}: {c:2d}{'q' if quiet else ' '} {value:.3f} ({100 * dev:+.1f} %)")
            print(f"{f:5g} Hz {x_mm:5.1f} mm  last 20: {late:.3f} +- {sd:.3f} | "
                  + " | ".join(cells), flush=True)
    print(f"{count} spheres, {len(points)} points, {n} cycles each, seed {seed}")
    for w in specs:
        d = np.asarray(devs[w])
        q = np.asarray(quiet_devs[w])
        print(f"{w}: stops at {np.median(stops[w]):.0f} (median), {np.mean(stops[w]):.1f} (mean); "
              f"within 1 / 5 / 10 %: {(d <= 0.01).sum()} / {(d <= 0.05).sum()} / "
              f"{(d <= 0.1).sum()} of {len(points)}, worst {100 * d.max():.1f} %; "
              f"quiet stops {q.size}" + (f", worst {100 * q.max():.1f} %" if q.size else ""))


if __name__ == "__main__":
    main(sys.argv[1:])
