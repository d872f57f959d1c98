"""Free flights (multiple time stepping in the Gear kernel) over the design map.

Run ``python benchmarks/bench_free_flights.py`` (``--quick``: four points). For each kind
of point (the paper's damper, 32 spheres, random packing as a map uses it, plus the lattice,
16 and 96 spheres and the full container) it runs the same excitation with
``gear_free_flight`` on and off and prints CPU seconds, steps, the share of spheres a step
integrated, the loss factor of both and the ledger closure. The loss factors differ within
the spread of a chaotic bed (the trajectories part at rounding level, as any two runs that
differ in the last bit); the physics checks are in tests/dem/test_free_flights.py.
"""

from __future__ import annotations

import argparse
import dataclasses
import time

from pdamper.dem import HarmonicMotion, warmup
from pdamper.models import DEMDamper
from pdamper.parameters import PAPER_DAMPER

#: (label, frequency [Hz], amplitude [m], spheres, packing, cycles)
POINTS = [
    ("slow corner", 2.0, 0.2, 32, "random", 4),
    ("fast corner", 20.0, 0.2, 32, "random", 8),
    ("small stroke", 20.0, 0.001, 32, "random", 8),
    ("tuned point", 10.0, 0.032, 32, "random", 8),
    ("rattling", 10.0, 0.015, 32, "random", 8),
    ("mid map", 5.0, 0.05, 32, "random", 8),
    ("tuned, lattice", 10.0, 0.032, 32, "lattice", 8),
    ("tuned, 16 spheres", 10.0, 0.032, 16, "random", 8),
    ("tuned, 96 spheres", 10.0, 0.032, 96, "random", 8),
    ("full container", 20.0, 0.032, 192, "lattice", 1),
]
QUICK = ("fast corner", "tuned point", "mid map", "tuned, 96 spheres")


def run(f, x, n, packing, cycles, free_flight):
    damper = dataclasses.replace(PAPER_DAMPER, count=n)
    sim = DEMDamper(damper, packing=packing).build_engine(HarmonicMotion(x, f))
    sim.gear_free_flight = free_flight
    c0 = time.process_time()
    res = sim.run(cycles / f, sample_rate=2000.0)
    cpu = time.process_time() - c0
    eta = res.complex_power(min(2, cycles - 1)).loss_factor
    return cpu, res, eta


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    warmup()
    print("Free flights in the Gear kernel: the same run with gear_free_flight on / off "
          "(CPU s, one core; settling included)")
    print(f"{'point':<18} {'f':>5} {'X mm':>6} {'n':>4} {'cyc':>3} {'CPU off':>8} "
          f"{'CPU on':>8} {'gain':>5} {'stepped':>7} {'steps on/off':>12} {'eta off':>8} "
          f"{'eta on':>8} {'ledger on':>9}")
    gains = []
    for label, f, x, n, packing, cycles in POINTS:
        if args.quick and label not in QUICK:
            continue
        c_off, r_off, e_off = run(f, x, n, packing, cycles, False)
        c_on, r_on, e_on = run(f, x, n, packing, cycles, True)
        gains.append((c_off / c_on, label))
        print(f"{label:<18} {f:>5g} {1e3 * x:>6g} {n:>4d} {cycles:>3d} {c_off:>8.2f} "
              f"{c_on:>8.2f} {c_off / c_on:>5.2f} {r_on.stepped_fraction:>7.2f} "
              f"{r_on.steps / r_off.steps:>12.3f} {e_off:>8.4f} {e_on:>8.4f} "
              f"{r_on.energy_balance_error():>9.1e}", flush=True)
    gains.sort()
    print(f"gain (CPU off / on): worst {gains[0][0]:.2f} ({gains[0][1]}), "
          f"median {gains[len(gains) // 2][0]:.2f}, best {gains[-1][0]:.2f} ({gains[-1][1]})")


if __name__ == "__main__":
    main()
