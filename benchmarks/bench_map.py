"""Benchmark of the DEM effective-field map (paper Fig. 5) on dask.distributed.

Run ``python benchmarks/bench_map.py`` (the paper's 14 x 24 grid, 32 spheres, every core;
``--frequency``/``--amplitude`` for another grid, ``--workers N``, ``--packing random``,
``--out FILE`` to keep the map). Prints

* the total wall time of the map, the per-point wall time (median, mean, worst and where),
  points per frequency, the cycles the points needed, steady / transient / failed counts;
* the LIGGGHTS 3.8 estimates for the same simulated time, on the same number of cores
  (LIGGGHTS' measured CPU cost per step of 32 spheres, scaled with the count): at the step
  its users take, 1 us (0.19 Rayleigh times of the benchmark spheres), the default of the
  side-by-side comparison ``benchmarks/liggghts/compare.py``; then, finer, at the step of
  its ``--liggghts-step verlet`` (at each point the step pdamper's velocity Verlet takes
  there, 0.28-0.54 us, which resolves the contacts to the accuracy of the verification
  table). ``--json`` also keeps ``liggghts_estimate_seconds``, 0.2 Rayleigh times at an
  older measured 4.69 wall s per simulated second (docs/performance.md), superseded by the 1 us
  estimate at the measured cost per step;
* the largest overlap / radius and the fastest impact over the map (the large-overlap
  regime of the fast corners, docs/dem.md);
* the agreement with the analytical map on the same grid (share of cells whose motion
  modes agree, median |delta eta| per analytical mode) and the DEM loss factor at the
  stroke nearest X_opt for f >= 8 Hz, the numbers docs/fields.md and the case-study table
  report.

``--json FILE`` writes all of it. The machine's load matters (shared 2-core VM): the
benchmark prints ``os.getloadavg()`` before and after.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

#: LIGGGHTS 3.8, benchmark damper, step 0.2 Rayleigh times, one core (docs/performance.md).
LIGGGHTS_WALL_PER_SIMULATED_SECOND = 4.69
#: The step LIGGGHTS users take for the benchmark spheres (0.19 Rayleigh times) [s].
LIGGGHTS_USERS_STEP = 1e-6
#: LIGGGHTS 3.8, benchmark damper of 32 spheres, CPU seconds per step: 11-14 us over the
#: kinds of point of ``benchmarks/liggghts/compare.py`` (docs/performance.md, "Summary"); the middle.
LIGGGHTS_CPU_PER_STEP_32 = 12.5e-6


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frequency", default="2Hz:20Hz:14")
    ap.add_argument("--amplitude", default="1mm:200mm:24")
    ap.add_argument("--particles", type=int, default=32)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--packing", default=None,
                    help="initial packing of the runs, random (a map's default) or lattice")
    ap.add_argument("--cycles", default=None, help="'auto' (default) or a number (paper: 8)")
    ap.add_argument("--quiet-window-cycles", type=int, default=None,
                    help="windows of the rule for quiet beds (0: the full window only; "
                         "default: the scenario's)")
    ap.add_argument("--quiet-windows", type=int, default=None,
                    help="number of windows of the rule for quiet beds (default: the "
                         "scenario's)")
    ap.add_argument("--quiet-skip-cycles", type=int, default=None,
                    help="cycles the rule for quiet beds skips (default: the scenario's)")
    ap.add_argument("--transient-tolerance", type=float, default=None,
                    help="Gear tolerance of the start from rest (default: the scenario's; "
                         "1e-5, Gear's own, for none)")
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)

    from pdamper.analysis.fields import effective_field, field_agreement
    from pdamper.analysis.modes import MotionMode
    from pdamper.dem import HarmonicMotion
    from pdamper.io.scenario import load_scenario
    from pdamper.models import AnalyticalDamper
    from pdamper.runs.maps import run_map
    from pdamper.sweep.cluster import default_workers

    overrides = {"map.frequency": args.frequency, "map.amplitude": args.amplitude,
                 "particles.count": args.particles, "map.dem_packing": args.packing,
                 "dem.cycles": None if args.cycles in (None, "auto") else int(args.cycles)}
    if args.cycles == "auto":
        overrides["dem.cycles"] = "auto"
    if args.quiet_window_cycles is not None:
        overrides["dem.quiet_window_cycles"] = args.quiet_window_cycles
    if args.quiet_windows is not None:
        overrides["dem.quiet_windows"] = args.quiet_windows
    if args.quiet_skip_cycles is not None:
        overrides["dem.quiet_skip_cycles"] = args.quiet_skip_cycles
    overrides["dem.transient_tolerance"] = args.transient_tolerance
    sc = load_scenario(None, overrides)
    workers = args.workers or default_workers()
    load0 = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        out = args.out or Path(tmp) / "fields.nc"
        t0 = time.perf_counter()
        run = run_map(sc, "dem", out=out, workers=workers)
        total = time.perf_counter() - t0
    load1 = os.getloadavg()
    ds = run.dataset
    f = ds["frequency"].values
    x = ds["amplitude"].values
    ok = ds["status"].values == 0
    wall = ds["point_seconds"].values
    cycles = ds["cycles"].values.astype(float)
    model = sc.map_model("dem")
    settle = model.build_engine(HarmonicMotion(0.01, 10.0)).settle_time  # same for every point
    needed = np.where(ok, cycles, np.nan)
    simulated = np.nansum(needed / f[:, None] + settle)  # what a run until steady needs
    liggghts = simulated * LIGGGHTS_WALL_PER_SIMULATED_SECOND / workers
    # at the step compare.py gives LIGGGHTS at each point (pdamper's Verlet step there); the
    # cost per step scaled with the count (an upper bound: 192 spheres measured 56 us, 4.5x)
    steps = 0.0
    for a, fa in enumerate(f):
        for b, xb in enumerate(x):
            if ok[a, b]:
                dt = model.build_engine(HarmonicMotion(float(xb), float(fa))).time_step
                steps += (cycles[a, b] / fa + settle) / dt
    per_step = LIGGGHTS_CPU_PER_STEP_32 * (args.particles / 32) / workers
    liggghts_accurate = steps * per_step
    liggghts_users = simulated / LIGGGHTS_USERS_STEP * per_step
    i, j = np.unravel_index(np.nanargmax(wall), wall.shape)
    overlap = ds["max_overlap_ratio"].values
    impact = ds["max_impact_velocity"].values
    ana = effective_field(AnalyticalDamper(sc.damper()), f, x)
    agr = field_agreement(ds, ana)
    jx = int(np.argmin(np.abs(x - sc.damper().optimal_stroke)))
    near = ok[:, jx] & (f >= 8.0)
    eta_xopt = ds["loss_factor"].values[near, jx]
    result = {
        "grid": [int(f.size), int(x.size)], "points": int(ok.size), "workers": workers,
        "quiet_window_cycles": sc.dem.quiet_window_cycles,
        "quiet_windows": sc.dem.quiet_windows,
        "quiet_skip_cycles": sc.dem.quiet_skip_cycles,
        "quiet_cells": int((ds["quiet_window"].values == 1).sum()),
        "transient_tolerance": sc.dem.transient_tolerance,
        "packing": sc.for_map().dem.packing, "cycles_option": sc.dem.cycles,
        "total_seconds": total,
        "per_point_seconds": {"median": float(np.nanmedian(wall)),
                              "mean": float(np.nanmean(wall)), "max": float(np.nanmax(wall)),
                              "max_at": {"frequency": float(f[i]), "amplitude": float(x[j])}},
        "per_point_by_frequency": {f"{fi:.3g}": float(np.nanmedian(wall[k]))
                                   for k, fi in enumerate(f)},
        "cycles_needed": {"median": float(np.nanmedian(np.where(ok, cycles, np.nan))),
                          "max": float(np.nanmax(np.where(ok, cycles, np.nan)))},
        "steady": agr["steady"], "failed": agr["failed"],
        "transient": int(((ds["stationary"].values == 0) & ok).sum()),
        "simulated_seconds": float(simulated),
        "liggghts_estimate_seconds": float(liggghts),
        "liggghts_estimate_at_accuracy_step_seconds": float(liggghts_accurate),
        "liggghts_estimate_at_users_step_seconds": float(liggghts_users),
        "max_overlap_ratio": float(np.nanmax(np.where(ok, overlap, np.nan))),
        "max_impact_velocity": float(np.nanmax(np.where(ok, impact, np.nan))),
        "agreement": agr,
        "eta_near_x_opt_f_ge_8hz": {"x_mm": float(x[jx] * 1e3),
                                    "values": eta_xopt.tolist(),
                                    "max": float(eta_xopt.max()) if eta_xopt.size else None},
        "load_average_before_after": [load0[0], load1[0]],
        "errors": sorted({e.split(" (")[0] for e in ds["error"].values.ravel() if e}),
    }
    _print(result, MotionMode)
    if args.json:
        args.json.write_text(json.dumps(result, indent=2))
    return result


def _print(r: dict, MotionMode) -> None:  # noqa: N803
    p = r["per_point_seconds"]
    print(f"DEM map {r['grid'][0]} x {r['grid'][1]} ({r['points']} points), 32 spheres, "
          f"packing {r['packing']}, cycles {r['cycles_option']}, {r['workers']} workers")
    print(f"  total wall time        {r['total_seconds']:.1f} s "
          f"({r['total_seconds'] / r['points']:.2f} s per point on {r['workers']} workers)")
    print(f"  per point (one core)   median {p['median']:.2f} s, mean {p['mean']:.2f} s, worst "
          f"{p['max']:.1f} s at f = {p['max_at']['frequency']:.3g} Hz, "
          f"X = {p['max_at']['amplitude'] * 1e3:.3g} mm")
    print("  median per point by f  " + ", ".join(
        f"{k} Hz: {v:.2f} s" for k, v in r["per_point_by_frequency"].items()))
    print(f"  cycles needed          median {r['cycles_needed']['median']:.0f}, "
          f"max {r['cycles_needed']['max']:.0f}; {r['quiet_cells']} cells judged quiet "
          f"(quiet rule: {r['quiet_windows']} x {r['quiet_window_cycles']} cycles after "
          f"{r['quiet_skip_cycles']}; start from rest at Gear tolerance "
          f"{r['transient_tolerance']:g})")
    print(f"  steady / transient / failed   {r['steady']} / {r['transient']} / {r['failed']}")
    if r["errors"]:
        print("  errors: " + "; ".join(r["errors"][:3]))
    print(f"  simulated time needed  {r['simulated_seconds']:.0f} s (cycles until steady and "
          "settling, every point)")
    print(f"  LIGGGHTS estimate      {r['liggghts_estimate_at_users_step_seconds']:.0f} s on "
          f"the same cores at its users' step, {1e6 * LIGGGHTS_USERS_STEP:g} us "
          f"({1e6 * LIGGGHTS_CPU_PER_STEP_32:g} us per step of 32 spheres, the same cycles); "
          f"finer, at pdamper's Verlet step at each point (compare.py --liggghts-step verlet) "
          f"{r['liggghts_estimate_at_accuracy_step_seconds']:.0f} s")
    print(f"  largest overlap        {100 * r['max_overlap_ratio']:.1f} % of the radius, "
          f"fastest impact {r['max_impact_velocity']:.1f} m/s")
    a = r["agreement"]
    print(f"  modes agree with the analytical map in {100 * a['mode_agreement']:.0f} % of "
          f"{a['cells']} cells; median |delta eta| {a['median_abs_delta_eta']:.3f}")
    for label, by in a["by_mode"].items():
        print(f"    {MotionMode.from_label(label).title:26s} {by['cells']:4d} cells, "
              f"{100 * by['mode_agreement']:3.0f} % same mode, median |delta eta| "
              f"{by['median_abs_delta_eta']:.3f}")
    e = r["eta_near_x_opt_f_ge_8hz"]
    if e["max"] is not None:
        print(f"  DEM eta at X = {e['x_mm']:.1f} mm (nearest X_opt), f >= 8 Hz: "
              f"{', '.join(f'{v:.2f}' for v in e['values'])}; max {e['max']:.3f} "
              "(paper: 1.25)")
    la = r["load_average_before_after"]
    print(f"  load average before/after: {la[0]:.2f} / {la[1]:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
