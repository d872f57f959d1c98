"""Benchmark: the cost of N DEM realisations on the sweep engine against one run.

Run ``python benchmarks/bench_realisations.py`` (N = 4 on 2 workers; ``--count``,
``--workers``, ``--level 2`` or ``3`` for one of the two, ``--json FILE``). For each level
it times

* one run in this process (the baseline ``t1``: a Level II DEM run at 10 Hz / 32 mm, 32
  spheres, 8 cycles; a Level III model 1 free vibration of 0.8 s, 32 spheres);
* the N realisations in this process, one after another (``serial``);
* the N realisations on a local dask cluster of ``--workers`` processes (``parallel``,
  the cluster's start included), and the cluster's start on its own;

and prints the ratio ``parallel / t1`` next to the ideal ``N / workers`` (the cost of N
realisations scales with N / cores when each worker has a core of its own), the parallel
efficiency ``N t1 / (workers x parallel)`` and the same without the cluster's start. Every
run starts from a random packing (seeds 0 .. N-1). The kernels are compiled (or loaded
from the cache) before any timing.

The machine's load matters (a shared 2-core VM): ``os.getloadavg()`` is printed before and
after, and the figures are only as good as the cores the workers got.
"""

from __future__ import annotations

import argparse
import json
import os
import time


def _timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def _level2(sc, n, workers):
    from pdamper.reports.realisations import realisation_point, run_realisations

    _, t1 = _timed(lambda: realisation_point({"seed": int(sc.dem.seed)}, scenario=sc))
    serial, ts = _timed(lambda: run_realisations(sc, n, serial=True))
    par, tp = _timed(lambda: run_realisations(sc, n, workers=workers))
    runs = [r["wall_seconds"] for r in serial.runs]
    return t1, ts, tp, runs, par.workers


def _level3(sc, n, workers):
    from pdamper.reports.realisations import level3_point, run_level3_realisations

    _, t1 = _timed(lambda: level3_point({"seed": int(sc.dem.seed)}, scenario=sc,
                                        model_name="dem"))
    serial, ts = _timed(lambda: run_level3_realisations(sc, n, "dem", serial=True))
    par, tp = _timed(lambda: run_level3_realisations(sc, n, "dem", workers=workers))
    return t1, ts, tp, serial.run_seconds, par.workers


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=4, help="realisations N (default 4)")
    ap.add_argument("--workers", type=int, default=2, help="dask worker processes (default 2)")
    ap.add_argument("--level", choices=("2", "3", "both"), default="both")
    ap.add_argument("--json", default=None, help="write the figures to this file")
    args = ap.parse_args(argv)

    from pdamper.dem import warmup
    from pdamper.io.scenario import load_scenario
    from pdamper.sweep.cluster import open_client

    load0 = os.getloadavg()
    compile_s = warmup(("gear",))
    print(f"load average before: {load0[0]:.2f} {load0[1]:.2f} {load0[2]:.2f}; "
          f"{os.cpu_count()} cores; kernels compiled/loaded in {compile_s:.1f} s")

    def start():
        with open_client(args.workers):
            pass

    _, cluster_s = _timed(start)
    print(f"a local cluster of {args.workers} workers starts and stops in {cluster_s:.2f} s")
    n, w = args.count, args.workers
    base = {"dem.packing": "random", "dem.seed": 0, "particles.count": 32}
    cases = {
        "2": ("Level II DEM run, 10 Hz / 32 mm, 8 cycles", _level2,
              {**base, "excitation.frequency": "10Hz", "excitation.amplitude": "32mm",
               "dem.cycles": 8}),
        "3": ("Level III model 1, 0.8 s", _level3,
              {**base, "simulation.duration": "0.8s", "optimization.at": "0.75s"}),
    }
    out = {"count": n, "workers": w, "cores": os.cpu_count(), "compile_seconds": compile_s,
           "cluster_start_seconds": cluster_s, "load_before": list(load0)}
    for level in ("2", "3") if args.level == "both" else (args.level,):
        what, fn, overrides = cases[level]
        t1, ts, tp, runs, got = fn(load_scenario(None, overrides), n, w)
        ideal = n / w
        eff = n * t1 / (w * tp)
        eff_run = n * t1 / (w * max(tp - cluster_s, 1e-9))
        print(f"{what}: one run {t1:.2f} s; {n} in this process {ts:.2f} s "
              f"({ts / t1:.2f} x one); {n} on {got} workers {tp:.2f} s ({tp / t1:.2f} x one, "
              f"ideal {ideal:.2f}); efficiency {eff * 100:.0f} % "
              f"({eff_run * 100:.0f} % without the cluster's start); runs "
              + ", ".join(f"{r:.2f}" for r in runs) + " s")
        out[f"level{level}"] = {"what": what, "one_seconds": t1, "serial_seconds": ts,
                                "parallel_seconds": tp, "parallel_over_one": tp / t1,
                                "ideal_ratio": ideal, "efficiency": eff,
                                "efficiency_without_cluster_start": eff_run,
                                "run_seconds": runs, "workers": got}
    load1 = os.getloadavg()
    out["load_after"] = list(load1)
    print(f"load average after: {load1[0]:.2f} {load1[1]:.2f} {load1[2]:.2f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=2)
    return out


if __name__ == "__main__":
    main()
