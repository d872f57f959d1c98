"""Speed of the analytical bed model on the paper's 14 x 24 (f, X) map (issue target:
well under one second), and of the Level III optimisation.

Run: ``python benchmarks/bench_analytic.py``
"""

from __future__ import annotations

import time

import numpy as np

from pdamper.analysis.analytical import bed_response
from pdamper.design import optimize_particle_count
from pdamper.models import AnalyticalDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_INITIAL_DISPLACEMENT, PAPER_STRUCTURE


def best_of(fn, repeat=5):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    f = np.linspace(2, 20, 14)[:, None]
    x = np.linspace(0.001, 0.2, 24)[None, :]
    t_map = best_of(lambda: bed_response(f, x, 0.1, 0.132))
    print(f"analytical map 14 x 24 (336 points): {t_map * 1e3:8.1f} ms "
          f"({t_map / 336 * 1e6:.0f} us/point)  target < 1000 ms")
    f2 = np.linspace(2, 20, 140)[:, None]
    x2 = np.linspace(0.001, 0.2, 240)[None, :]
    t_big = best_of(lambda: bed_response(f2, x2, 0.1, 0.132), repeat=2)
    print(f"analytical map 140 x 240 (33600 points): {t_big * 1e3:8.1f} ms "
          f"({t_big / 33600 * 1e6:.1f} us/point)")
    # one point per call, as the harmonic balance's root search asks (CPU time: the
    # machine is often shared), with gravity and without (long flights)
    pts = [(float(a), float(b)) for a in np.linspace(2, 20, 7) for b in np.linspace(0.001, 0.2, 12)]
    for g in (9.81, 0.0):
        t0 = time.thread_time()
        for fi, xi in pts:
            bed_response(fi, xi, 0.1, 0.132, gravity=g)
        t_one = (time.thread_time() - t0) / len(pts)
        print(f"one point per call, g = {g:4.2f} m/s^2 ({len(pts)} points): "
              f"{t_one * 1e6:8.0f} us CPU per point")
    t_opt = best_of(lambda: optimize_particle_count(PAPER_STRUCTURE, PAPER_DAMPER,
                                                    PAPER_INITIAL_DISPLACEMENT, 0.8,
                                                    AnalyticalDamper), repeat=3)
    print(f"optimisation, 12 candidates to 0.8 s:   {t_opt * 1e3:8.1f} ms")


if __name__ == "__main__":
    main()
