"""Throughput of ``pdamper map --model dem`` against LIGGGHTS 3.8 on the same damper, side
by side in one run: ``python benchmarks/liggghts/compare.py`` (``--quick``: three kinds).

For each kind of point of the paper's map (slow and fast corners, small stroke, the tuned
point, a rattling point, the full container) it runs

* ``pdamper map --model dem`` on a 3 x 3 map ending at the point (0.9 f, 0.95 f, f) x
  (0.9 X, 0.95 X, X), inside the paper's envelope at its corners, ``--serial`` (one core,
  no dask workers to start), the whole process (python start, import, numba cache load, settling,
  8 cycles per point), one core;
* LIGGGHTS (``stdbuf -o0 -e0 liggghts -in damper.in``, the deck beside this file) on the
  point itself: settling and ``--liggghts-cycles`` cycles (its cost per step is constant,
  so the throughput does not depend on the length), at the step that pdamper's velocity
  Verlet takes by default there (0.02 of the Hertz contact time at the fastest impact it
  expects: the step at which a velocity-Verlet code resolves the contacts to the accuracy of
  the verification table of docs/dem.md), and, for reference, at 0.2 Rayleigh times
  (LIGGGHTS' usual advice, coarser than the contacts need at the fast points);

and prints the cost of one point (settling + 8 cycles) of each, their ratio, and the
throughput (simulated seconds of excitation per second) of the whole map process, in CPU
seconds (``getrusage``: robust on a loaded machine; wall seconds in brackets). pdamper's
per-point cost is the map's less its start-up (measured apart and printed first: a whole
map process of one cheap point), which a map pays once; LIGGGHTS' is its cost per step times
the steps of one point.

``--integrator`` sets pdamper's integrator (default the model's, Gear; ``auto`` hands a
run over to velocity Verlet where Gear's steps are held by its stability limit).
``--packing`` sets pdamper's initial packing (default the deck's lattice; a map's default is
``auto``, random where it fits). Every pdamper run here does the paper's 8 cycles, as the
deck; a map's default runs until steady (docs/fields.md), which changes the cycles, not the
cost per cycle.
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

from liggghts_damper import available, run_liggghts  # noqa: E402

KINDS = [  # name, f [Hz], X [mm], spheres
    ("slow corner", 2.0, 200.0, 32),
    ("fast corner", 20.0, 200.0, 32),
    ("small stroke", 20.0, 1.0, 32),
    ("tuned point", 10.0, 32.0, 32),
    ("rattling", 10.0, 15.0, 32),
    ("full container", 20.0, 32.0, 192),
]
QUICK = ["fast corner", "small stroke", "tuned point"]
CYCLES = 8


def _child(cmd) -> tuple[float, float, subprocess.CompletedProcess]:
    c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr[-2000:])
    return wall, (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime), proc


def startup(packing: str, integrator: str = "gear") -> tuple[float, float, float]:
    """CPU seconds of: the import of the CLI and models; that + the numba cache load of the
    DEM kernels a run with ``integrator`` calls (a ``pdamper dem``'s start-up: the kernels of
    the other integrators are not loaded); and a whole ``pdamper map --model dem``
    process of one cheap point (one cycle at 20 Hz / 1 mm after settling: 0.06 s of CPU,
    left in, so the start-up is slightly overstated and pdamper's per-point cost with it),
    the start-up a map pays once (its imports of xarray, NetCDF and the sweep engine)."""
    _, imp, _ = _child([sys.executable, "-c", "import pdamper.cli, pdamper.models"])
    _, load, _ = _child([sys.executable, "-c",
                         "import pdamper.dem.simulation as s; from pdamper.dem import warmup; "
                         f"warmup(integrators=({integrator!r},), motions=('harmonic',))"])
    with tempfile.TemporaryDirectory() as tmp:
        scenario = Path(tmp) / "s.toml"
        scenario.write_text(f'[dem]\ncycles = 1\nskip_cycles = 0\n\n[map]\n'
                            f'dem_packing = "{packing}"\n')
        _, mapped, _ = _child([sys.executable, "-m", "pdamper", "map", "--model", "dem",
                               "--frequency", "20Hz", "--amplitude", "1mm", "--scenario",
                               str(scenario), "--serial", "--json"])
    return imp, load, mapped


def pdamper_map(f, x_mm, n, packing: str, scenario: Path, integrator: str = "gear") -> dict:
    # like for like with the deck: the paper's 8 cycles (a map's default runs until steady)
    scenario.write_text(f'[dem]\ncycles = {CYCLES}\nintegrator = "{integrator}"\n\n'
                        f'[map]\ndem_packing = "{packing}"\n')
    cmd = [sys.executable, "-m", "pdamper", "map", "--model", "dem", "--particles", str(n),
           "--frequency", f"{0.9 * f:g}Hz:{f:g}Hz:3", "--scenario", str(scenario),
           "--amplitude", f"{0.9 * x_mm:g}mm:{x_mm:g}mm:3", "--serial", "--json"]
    wall, cpu, _ = _child(cmd)
    sim = 3 * CYCLES * sum(1.0 / g for g in (0.9 * f, 0.95 * f, f))
    return {"wall": wall, "cpu": cpu, "simulated": sim, "points": 9}


def verlet_step(f, x_mm, n) -> float:
    from pdamper.dem import HarmonicMotion
    from pdamper.models import DEMDamper
    from pdamper.parameters import PAPER_DAMPER

    eng = DEMDamper(PAPER_DAMPER.with_count(n)).engine(HarmonicMotion(x_mm * 1e-3, f))
    return eng.time_step, eng.rayleigh_time


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--liggghts-cycles", type=int, default=1)
    ap.add_argument("--packing", default="lattice", choices=["lattice", "random", "auto"],
                    help="pdamper's initial packing (the deck starts from the lattice; "
                    "LIGGGHTS' cost per step hardly depends on it)")
    ap.add_argument("--integrator", default="gear", choices=["gear", "verlet", "auto"],
                    help="pdamper's integrator (default gear, the model's default)")
    ap.add_argument("--kind", action="append", choices=[k[0] for k in KINDS],
                    help="run only this kind of point (repeatable)")
    args = ap.parse_args(argv)
    if not available():
        sys.exit("liggghts not found (Debian: apt-get install liggghts)")
    imp, load, mapped = startup(args.packing, args.integrator)
    print(f"pdamper packing: {args.packing}, integrator: {args.integrator}, {CYCLES} cycles "
          "per point")
    print(f"pdamper start-up (CPU s): import of the CLI and models {imp:.2f}, "
          f"import + numba cache load of the DEM kernels {load:.2f} (a `pdamper dem`), "
          f"a whole one-point map process {mapped:.2f} (a map's start-up)")
    print(f"\n{'kind':<15} {'f':>4} {'X/mm':>5} {'n':>4} | {'pdamper':>8} | {'LIGGGHTS dt':>11} "
          f"{'CPU us/step':>11} {'per point':>9} | {'ratio':>6} | {'map sim-s/CPU-s':>15} "
          f"{'ratio':>6} | {'ratio @0.2 t_R':>14}")
    print(f"{'':<15} {'':>4} {'':>5} {'':>4} | {'s/point':>8} | {'[s]':>11} {'':>11} "
          f"{'[s]':>9} | {'':>6} | {'(whole process)':>15} {'':>6} |")
    for name, f, x, n in KINDS:
        if (args.quick and name not in QUICK) or (args.kind and name not in args.kind):
            continue
        with tempfile.TemporaryDirectory() as tmp:
            p = pdamper_map(f, x, n, args.packing, Path(tmp) / "s.toml", args.integrator)
        per_point = max(p["cpu"] - mapped, 1e-9) / p["points"]
        dt, t_r = verlet_step(f, x, n)
        runs = []
        for step in (dt, 0.2 * t_r):
            lg = run_liggghts(f, x * 1e-3, count=n, dt=step, cycles=args.liggghts_cycles,
                              skip_cycles=0)
            settle = lg["steps"] * lg["dt"] - lg["simulated"]
            # one point: settling + 8 cycles at LIGGGHTS' (constant) cost per step
            runs.append((lg, lg["cpu"] / lg["steps"] * (settle + CYCLES / f) / lg["dt"]))
        (lg, lig_point), (_, lig_point_r) = runs
        map_tp = p["simulated"] / p["cpu"]
        lig_tp = (CYCLES / f) / lig_point
        print(f"{name:<15} {f:>4g} {x:>5g} {n:>4d} | {per_point:>8.3f} | {lg['dt']:>11.3g} "
              f"{1e6 * lg['cpu'] / lg['steps']:>11.1f} {lig_point:>9.1f} | "
              f"{lig_point / per_point:>5.0f}x | {map_tp:>6.3f} ({p['simulated'] / p['wall']:.3f}) "
              f"{map_tp / lig_tp:>5.0f}x | {lig_point_r / per_point:>13.0f}x", flush=True)


if __name__ == "__main__":
    main()
