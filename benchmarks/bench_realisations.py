"""Benchmark: the cost of N DEM realisations on the sweep engine against one run.

Run ``python benchmarks/bench_realisations.py`` (N = 4 on 2 workers; ``--count``,
``--workers``, ``--level 2`` or ``3`` for one of the two, ``--json FILE``). For each level
it times

* one run in this process (the baseline ``t1``: a Level II DEM run at 10 Hz / 32 mm, 32
  spheres, 8 cycles; a Level III model 1 free vibration of 0.8 s, 32 spheres);
* the N realisations in this process, one after another (``serial``);
* the N realisations as the commands run them: a new local dask cluster of ``--workers``
  processes, whose workers import pdamper and load the kernels on their first task
  (``cold``);
* the N realisations on warm workers (kernels loaded beforehand, timed apart): the
  scaling itself;

and prints each against ``t1``, the warm ratio next to the ideal ``N / workers`` (the cost
of N realisations scales with N / cores when each worker has a core of its own) and the
efficiency ``N t1 / (workers x warm)``; the cluster's start and the kernels' load are
fixed costs of a command, paid once however long its runs. Every run starts from a random
packing (seeds 0 .. N-1). The kernels are compiled (or loaded from the cache) in this
process before any timing.

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


def _warm_worker() -> float:
    """Load pdamper and the DEM kernels in a worker process (what its first task pays)."""
    from pdamper.dem import warmup

    return warmup(("gear",))


def _case(point, runner, sc, n, workers):
    """(t1, serial, cold, warm, worker start, run seconds, workers) of one kind of run."""
    from pdamper.sweep import run_sweep
    from pdamper.sweep.cluster import open_client

    # a seed of its own: a process keeps settled beds, which a realisation must not reuse
    _, t1 = _timed(lambda: point({"seed": int(sc.dem.seed) + 1000}))
    serial, ts = _timed(lambda: runner(sc, n, serial=True))
    cold, tc = _timed(lambda: runner(sc, n, workers=workers))
    seeds = [int(sc.dem.seed) + k for k in range(n)]
    with open_client(workers) as client:
        _, tw0 = _timed(lambda: client.run(_warm_worker))  # every worker loads the kernels
        warm, tw = _timed(lambda: run_sweep(point, [{"seed": s} for s in seeds], retries=0,
                                            client=client))
    return t1, ts, tc, tw, tw0, serial, warm.workers, [p.seconds for p in warm.points]


def _level2(sc, n, workers):
    import functools

    from pdamper.runs.realisations import realisation_point, run_realisations

    out = _case(functools.partial(realisation_point, scenario=sc), run_realisations, sc, n,
                workers)
    return (*out[:5], [r["wall_seconds"] for r in out[5].runs], *out[6:])


def _level3(sc, n, workers):
    import functools

    from pdamper.runs.realisations import level3_point, run_level3_realisations

    out = _case(functools.partial(level3_point, scenario=sc, model_name="dem"),
                lambda s, k, **o: run_level3_realisations(s, k, "dem", **o), sc, n, workers)
    return (*out[:5], out[5].run_seconds, *out[6:])


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=4, help="realisations N (default 4)")
    ap.add_argument("--cycles", type=int, default=8, help="Level II cycles (default 8)")
    ap.add_argument("--duration", default="0.8s", help="Level III duration (default 0.8 s)")
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
        "2": (f"Level II DEM run, 10 Hz / 32 mm, {args.cycles} cycles", _level2,
              {**base, "excitation.frequency": "10Hz", "excitation.amplitude": "32mm",
               "dem.cycles": args.cycles}),
        "3": (f"Level III model 1, {args.duration}", _level3,
              {**base, "simulation.duration": args.duration, "optimization.at": args.duration}),
    }
    out = {"count": n, "workers": w, "cores": os.cpu_count(), "compile_seconds": compile_s,
           "cluster_start_seconds": cluster_s, "load_before": list(load0)}
    for level in ("2", "3") if args.level == "both" else (args.level,):
        what, fn, overrides = cases[level]
        t1, ts, tc, tw, tw0, runs, got, on_workers = fn(load_scenario(None, overrides), n, w)
        ideal = n / w
        print(f"{what}: one run {t1:.2f} s; {n} in this process {ts:.2f} s "
              f"({ts / t1:.2f} x one); {n} on {got} workers as the commands run them (a "
              f"new cluster) {tc:.2f} s ({tc / t1:.2f} x one); on {got} warm workers "
              f"{tw:.2f} s ({tw / t1:.2f} x one, ideal {ideal:.2f}; {ts / tw:.2f} times "
              f"as fast as in this process, ideal {w}; efficiency "
              f"{n * t1 / (w * tw) * 100:.0f} %); loading the kernels on the workers "
              f"{tw0:.2f} s; runs in this process " + ", ".join(f"{r:.2f}" for r in runs)
              + " s, points on the warm workers " + ", ".join(f"{r:.2f}" for r in on_workers)
              + " s")
        out[f"level{level}"] = {"what": what, "one_seconds": t1, "serial_seconds": ts,
                                "cold_parallel_seconds": tc, "warm_parallel_seconds": tw,
                                "worker_kernel_load_seconds": tw0,
                                "warm_over_one": tw / t1, "cold_over_one": tc / t1,
                                "speedup_over_serial": ts / tw,
                                "ideal_ratio": ideal, "warm_efficiency": n * t1 / (w * tw),
                                "run_seconds": runs, "warm_point_seconds": on_workers,
                                "workers": got}
    load1 = os.getloadavg()
    out["load_after"] = list(load1)
    print(f"load average after: {load1[0]:.2f} {load1[1]:.2f} {load1[2]:.2f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=2)
    return out


if __name__ == "__main__":
    main()
