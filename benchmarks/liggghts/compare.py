"""Throughput of pdamper against LIGGGHTS 3.8 on the same damper, side by side in one run:
``python benchmarks/liggghts/compare.py`` (``--quick``: three kinds).

LIGGGHTS' time step is ``--liggghts-step`` (repeatable: one comparison per step):

* ``1us`` (default): the step LIGGGHTS users take for these spheres, about 0.2 Rayleigh
  times (steel, R = 5 mm: t_R = pi R sqrt(rho/G) / (0.1631 nu + 0.8766) = 5.33 us, so
  1 us = 0.19 t_R), and the step of published LIGGGHTS runs of this damper;
* ``verlet``: at each point the step that pdamper's velocity Verlet takes there by default
  (0.02 of the Hertz contact time at the fastest impact it expects, 0.28-0.54 us over the
  kinds below: the step at which an explicit code resolves the contacts to the accuracy of
  the verification table of docs/verification.md), 2-3.5x finer than the users' step;
* ``0.2tR`` (a fraction of the Rayleigh time) or a step with its unit (``500ns``,
  ``0.7us``, ``1e-6s``).

The step is rounded so that whole steps fill the deck's force windows (exact for 1 us at
every frequency used here). Three comparisons, each printing the cores each code used:

* **per point** (default): for each kind of point of the paper's map (slow and fast
  corners, small stroke, the tuned point, a rattling point, the full container),
  ``pdamper map --model dem`` on an N x N map ending at the point (``--points N``, default
  3: (0.9 f .. f) x (0.9 X .. X), inside the paper's envelope at its corners), ``--serial``
  (one core), the whole process (python start, import, numba cache load, settling, 8 cycles
  per point); and LIGGGHTS (``stdbuf -o0 -e0 liggghts -in damper.in``, the deck beside this
  file, one serial process: one core) on the point itself, settling and
  ``--liggghts-cycles`` cycles (its cost per step is constant, so the throughput does not
  depend on the length). It prints the cost of one point (settling + 8 cycles) of each,
  their ratio, and the throughput (simulated seconds of excitation per CPU second) of the
  whole map process, in CPU seconds (``getrusage``: robust on a loaded machine; wall
  seconds in brackets). pdamper's per-point cost is the map's less its start-up (measured
  apart and printed first: a whole map process of one cheap point), which a map pays once;
  LIGGGHTS' is its cost per step times the steps of one point.
* ``--map FxX``: a whole F x X map (``--frequency LO:HI`` in Hz, ``--amplitude LO:HI`` in
  mm, evenly spaced; default the paper's map, 2-20 Hz, 1-200 mm), 8 cycles per point, on
  ``--workers W`` cores each: pdamper's map with W dask workers (``--serial`` for 1), and
  LIGGGHTS running every point in full, W processes at a time. Wall and CPU seconds of both
  (the map's whole process; LIGGGHTS' processes), ratio.
* ``--single HZ MM``: one run as a user types it, ``pdamper dem --frequency HZ --amplitude
  MM --cycles 8`` (the whole process, start-up included) against the whole LIGGGHTS process
  of the same run (settling + 8 cycles), ``--repeat`` times interleaved; medians, ranges,
  and both loss factors (cycles 3-8).

* ``--protocol lattice|random``: not the speed but the answers: loss factor and effective
  mass of both codes at 12 points over 5-20 Hz x 10-80 mm (``--point HZ MM`` for others),
  from the same jittered lattices or from ``--seeds N`` random packings of each code
  (``agreement.py`` beside this file; the tables of docs/agreement.md, "The lattice in
  three codes" and "Random beds"); ``--friction spring`` pdamper with LIGGGHTS'
  tangential law (a spring with a Coulomb limit; Verlet), ``--liggghts-step`` LIGGGHTS'
  step there (first value; default 1 us); ``--law`` pdamper's damping law (repeatable;
  default tsuji and exact for the lattice, tsuji for random beds), ``--out FILE`` the runs
  as JSON.

``--integrator`` sets pdamper's integrator (default the model's, Gear; ``auto`` hands a
run over to velocity Verlet where Gear's steps are held by its stability limit).
``--packing`` sets pdamper's initial packing (default the deck's lattice; a map's default is
``auto``, random where it fits). Every pdamper run here does the paper's 8 cycles, as the
deck; a map's default runs until steady (docs/fields.md), which changes the cycles, not the
cost per cycle.
"""

from __future__ import annotations

import argparse
import json
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

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
USERS_STEP = "1us"
_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}


def _x(ratio: float) -> str:
    """A ratio as printed: two digits below 10x (0.8x, 2.5x), whole above."""
    return f"{ratio:.1f}x" if ratio < 10 else f"{ratio:.0f}x"


def _cpu_children() -> float:
    c = resource.getrusage(resource.RUSAGE_CHILDREN)
    return c.ru_utime + c.ru_stime


def _child(cmd) -> tuple[float, float, subprocess.CompletedProcess]:
    c0 = _cpu_children()
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr[-2000:])
    return wall, _cpu_children() - c0, proc


def liggghts_step(spec: str, f: float, x_mm: float, n: int) -> float:
    """LIGGGHTS' step [s] at the point from ``--liggghts-step`` (see the module docstring)."""
    verlet, t_r = _verlet_step(f, x_mm, n)
    if spec == "verlet":
        return verlet
    m = re.fullmatch(r"\s*([0-9.eE+-]+)\s*(tR|s|ms|us|ns)\s*", spec)
    if m is None:
        raise SystemExit(f"--liggghts-step: '{spec}' is not 'verlet', '<x>tR' or a step with "
                         f"a unit (s, ms, us, ns)")
    value = float(m.group(1))
    step = value * (t_r if m.group(2) == "tR" else _UNITS[m.group(2)])
    if not 1e-9 <= step <= 1e-5:
        raise SystemExit(f"--liggghts-step: {spec} is {step:g} s, outside 1 ns .. 10 us")
    return step


def _verlet_step(f, x_mm, n) -> tuple[float, float]:
    from pdamper.dem import HarmonicMotion
    from pdamper.models import DEMDamper
    from pdamper.parameters import PAPER_DAMPER

    eng = DEMDamper(PAPER_DAMPER.with_count(n)).build_engine(HarmonicMotion(x_mm * 1e-3, f))
    return eng.time_step, eng.rayleigh_time


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


def _axis(lo: float, hi: float, count: int, unit: str) -> str:
    return f"{hi:g}{unit}" if count == 1 else f"{lo:g}{unit}:{hi:g}{unit}:{count}"


def pdamper_map(freqs, amps_mm, n, packing: str, scenario: Path, integrator: str = "gear",
                workers: int = 1) -> dict:
    """A whole ``pdamper map --model dem`` process over ``freqs`` x ``amps_mm`` (evenly
    spaced), 8 cycles per point, on ``workers`` cores (1: ``--serial``)."""
    # like for like with the deck: the paper's 8 cycles (a map's default runs until steady)
    scenario.write_text(f'[dem]\ncycles = {CYCLES}\nintegrator = "{integrator}"\n\n'
                        f'[map]\ndem_packing = "{packing}"\n')
    cmd = [sys.executable, "-m", "pdamper", "map", "--model", "dem", "--particles", str(n),
           "--frequency", _axis(freqs[0], freqs[-1], len(freqs), "Hz"),
           "--amplitude", _axis(amps_mm[0], amps_mm[-1], len(amps_mm), "mm"),
           "--scenario", str(scenario), "--json"]
    cmd += ["--serial"] if workers == 1 else ["--workers", str(workers)]
    wall, cpu, _ = _child(cmd)
    sim = len(amps_mm) * CYCLES * sum(1.0 / g for g in freqs)
    return {"wall": wall, "cpu": cpu, "simulated": sim, "points": len(freqs) * len(amps_mm)}


def per_point(args) -> None:
    imp, load, mapped = startup(args.packing, args.integrator)
    print(f"pdamper packing: {args.packing}, integrator: {args.integrator}, {CYCLES} cycles "
          f"per point, a {args.points} x {args.points} map per kind")
    print("cores: pdamper 1 (`map --serial`), LIGGGHTS 1 (one serial process per point)")
    print(f"pdamper start-up (CPU s): import of the CLI and models {imp:.2f}, "
          f"import + numba cache load of the DEM kernels {load:.2f} (a `pdamper dem`), "
          f"a whole one-point map process {mapped:.2f} (a map's start-up)")
    print(f"\n{'kind':<15} {'f':>4} {'X/mm':>5} {'n':>4} | {'pdamper':>8} | "
          f"{'LIGGGHTS step':>14} {'dt':>9} {'CPU us/step':>11} {'per point':>9} | "
          f"{'ratio':>6} | {'map sim-s/CPU-s':>15} {'ratio':>6}")
    print(f"{'':<15} {'':>4} {'':>5} {'':>4} | {'s/point':>8} | {'':>14} {'[s]':>9} {'':>11} "
          f"{'[s]':>9} | {'':>6} | {'(whole process)':>15} {'':>6}")
    k = args.points
    for name, f, x, n in KINDS:
        if (args.quick and name not in QUICK) or (args.kind and name not in args.kind):
            continue
        freqs = list(np.linspace(0.9 * f, f, k)) if k > 1 else [f]
        amps = list(np.linspace(0.9 * x, x, k)) if k > 1 else [x]
        with tempfile.TemporaryDirectory() as tmp:
            p = pdamper_map(freqs, amps, n, args.packing, Path(tmp) / "s.toml",
                            args.integrator)
        point = max(p["cpu"] - mapped, 1e-9) / p["points"]
        map_tp = p["simulated"] / p["cpu"]
        for spec in args.liggghts_step:
            lg = run_liggghts(f, x * 1e-3, count=n, dt=liggghts_step(spec, f, x, n),
                              cycles=args.liggghts_cycles, skip_cycles=0)
            settle = lg["steps"] * lg["dt"] - lg["simulated"]
            # one point: settling + 8 cycles at LIGGGHTS' (constant) cost per step
            lig_point = lg["cpu"] / lg["steps"] * (settle + CYCLES / f) / lg["dt"]
            lig_tp = (CYCLES / f) / lig_point
            print(f"{name:<15} {f:>4g} {x:>5g} {n:>4d} | {point:>8.3f} | {spec:>14} "
                  f"{lg['dt']:>9.3g} {1e6 * lg['cpu'] / lg['steps']:>11.1f} "
                  f"{lig_point:>9.1f} | {_x(lig_point / point):>6} | {map_tp:>6.3f} "
                  f"({p['simulated'] / p['wall']:.3f}) {_x(map_tp / lig_tp):>6}", flush=True)


def _range(lohi: str, what: str) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in lohi.split(":"))
    except ValueError:
        raise SystemExit(f"--{what}: '{lohi}' is not LO:HI (numbers)") from None
    return lo, hi


def whole_map(args) -> None:
    m = re.fullmatch(r"(\d+)x(\d+)", args.map)
    if m is None:
        raise SystemExit(f"--map: '{args.map}' is not FxX, e.g. 4x4")
    nf, nx = int(m.group(1)), int(m.group(2))
    f_lo, f_hi = _range(args.frequency, "frequency")
    x_lo, x_hi = _range(args.amplitude, "amplitude")
    freqs = list(np.linspace(f_lo, f_hi, nf)) if nf > 1 else [f_hi]
    amps = list(np.linspace(x_lo, x_hi, nx)) if nx > 1 else [x_hi]
    w = args.workers
    print(f"{nf} x {nx} map, {f_lo:g}-{f_hi:g} Hz x {x_lo:g}-{x_hi:g} mm, 32 spheres, "
          f"{CYCLES} cycles per point; pdamper packing {args.packing}, integrator "
          f"{args.integrator}")
    print(f"cores: pdamper {w} ({'`map --serial`' if w == 1 else f'`map --workers {w}`'}), "
          f"LIGGGHTS {w} ({w} serial process{'es' if w > 1 else ''} at a time)")
    with tempfile.TemporaryDirectory() as tmp:
        p = pdamper_map(freqs, amps, 32, args.packing, Path(tmp) / "s.toml",
                        args.integrator, workers=w)
    print(f"pdamper  : wall {p['wall']:8.1f} s, CPU {p['cpu']:8.1f} s (the whole map process)",
          flush=True)
    for spec in args.liggghts_step:
        jobs = [(f, x) for f in freqs for x in amps]

        def one(job, spec=spec):
            f, x = job
            return run_liggghts(f, x * 1e-3, dt=liggghts_step(spec, f, x, 32),
                                cycles=CYCLES, skip_cycles=2)

        c0, t0 = _cpu_children(), time.perf_counter()
        with ThreadPoolExecutor(max_workers=w) as pool:
            runs = list(pool.map(one, jobs))
        wall, cpu = time.perf_counter() - t0, _cpu_children() - c0
        steps = sum(r["steps"] for r in runs)
        print(f"LIGGGHTS : wall {wall:8.1f} s, CPU {cpu:8.1f} s at step {spec} "
              f"({1e6 * cpu / steps:.1f} us per step); ratio wall {_x(wall / p['wall'])}, "
              f"CPU {_x(cpu / p['cpu'])}", flush=True)


def single(args) -> None:
    f, x = args.single
    print(f"one run: `pdamper dem --frequency {f:g}Hz --amplitude {x:g}mm --cycles {CYCLES}` "
          f"(the whole process) against the whole LIGGGHTS process of the same run "
          f"(settling + {CYCLES} cycles), {args.repeat} rounds interleaved")
    print("cores: pdamper 1, LIGGGHTS 1 (one serial process)")
    cmd = [sys.executable, "-m", "pdamper", "dem", "--frequency", f"{f:g}Hz", "--amplitude",
           f"{x:g}mm", "--cycles", str(CYCLES), "--json"]
    pd, lg = [], {spec: [] for spec in args.liggghts_step}
    for _ in range(args.repeat):
        wall, cpu, proc = _child(cmd)
        pd.append((wall, cpu, json.loads(proc.stdout)["loss_factor"]))
        for spec in args.liggghts_step:
            r = run_liggghts(f, x * 1e-3, dt=liggghts_step(spec, f, x, 32), cycles=CYCLES,
                             skip_cycles=2)
            lg[spec].append((r["wall"], r["cpu"], r["loss_factor"]))

    def show(label, rows):
        w = [r[0] for r in rows]
        c = [r[1] for r in rows]
        print(f"{label:<22} wall {statistics.median(w):6.2f} s ({min(w):.2f}-{max(w):.2f}), "
              f"CPU {statistics.median(c):6.2f} s ({min(c):.2f}-{max(c):.2f}), loss factor "
              + " ".join(f"{r[2]:.3f}" for r in rows))
        return statistics.median(w), statistics.median(c)

    pw, pc = show("pdamper dem", pd)
    for spec, rows in lg.items():
        lw, lc = show(f"LIGGGHTS at {spec}", rows)
        print(f"{'':<22} ratio of medians: wall {_x(lw / pw)}, CPU {_x(lc / pc)}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--liggghts-step", action="append", default=None,
                    help=f"LIGGGHTS' time step: '{USERS_STEP}' (default, the users' step, "
                    "0.19 Rayleigh times), 'verlet' (pdamper's velocity-Verlet step at the "
                    "point), '<x>tR', or a step with a unit (repeatable)")
    ap.add_argument("--liggghts-cycles", type=int, default=1)
    ap.add_argument("--points", type=int, default=3,
                    help="pdamper's map per kind is N x N points ending at the point")
    ap.add_argument("--packing", default="lattice", choices=["lattice", "random", "auto"],
                    help="pdamper's initial packing (the deck starts from the lattice; "
                    "LIGGGHTS' cost per step hardly depends on it)")
    ap.add_argument("--integrator", default="gear", choices=["gear", "verlet", "auto"],
                    help="pdamper's integrator (default gear, the model's default)")
    ap.add_argument("--kind", action="append", choices=[k[0] for k in KINDS],
                    help="run only this kind of point (repeatable)")
    ap.add_argument("--map", default=None, metavar="FxX",
                    help="compare a whole map of F x X points instead (e.g. 4x4)")
    ap.add_argument("--frequency", default="2:20", help="--map's frequencies LO:HI [Hz]")
    ap.add_argument("--amplitude", default="1:200", help="--map's amplitudes LO:HI [mm]")
    ap.add_argument("--workers", type=int, default=1, help="--map's cores for each code")
    ap.add_argument("--single", type=float, nargs=2, default=None, metavar=("HZ", "MM"),
                    help="compare one `pdamper dem` run, the whole process, instead")
    ap.add_argument("--repeat", type=int, default=3, help="--single's rounds")
    ap.add_argument("--protocol", choices=["lattice", "random"], default=None,
                    help="compare the loss factors on this protocol instead (agreement.py)")
    ap.add_argument("--seeds", type=int, default=2,
                    help="--protocol: jitter seeds (lattice) or packings per code (random)")
    ap.add_argument("--law", action="append", choices=["tsuji", "exact", "gonthier"],
                    help="--protocol: pdamper's damping law (repeatable)")
    ap.add_argument("--point", type=float, nargs=2, action="append", metavar=("HZ", "MM"),
                    help="--protocol: this point instead of the grid (repeatable)")
    ap.add_argument("--out", default=None, help="--protocol: write the runs as JSON here")
    ap.add_argument("--friction", choices=["regularised", "spring"], default="regularised",
                    help="--protocol: pdamper's tangential law (spring: LIGGGHTS' own)")
    ap.add_argument("--converged", action="store_true",
                    help="--protocol lattice: also pdamper converged (Verlet at 0.005)")
    args = ap.parse_args(argv)
    args.liggghts_step = args.liggghts_step or [USERS_STEP]
    if args.points < 1 or args.workers < 1 or args.repeat < 1:
        ap.error("--points, --workers and --repeat must be at least 1")
    if not available():
        sys.exit("liggghts not found (Debian: apt-get install liggghts)")
    for spec in args.liggghts_step:  # bad steps fail before any run
        liggghts_step(spec, 10.0, 32.0, 32)
    if args.protocol:
        import agreement

        if args.seeds < 1:
            ap.error("--seeds must be at least 1")
        args.law = args.law or (["tsuji", "exact"] if args.protocol == "lattice" else ["tsuji"])
        # LIGGGHTS' step on the protocol: the users' 1 us unless given (a fixed step:
        # 0.25 us takes 4 x longer; at 80 mm 1 us is not converged, docs/agreement.md)
        agreement.LIGGGHTS_STEP = liggghts_step(args.liggghts_step[0], 10.0, 32.0, 32)
        agreement.main(args)
    elif args.single:
        single(args)
    elif args.map:
        whole_map(args)
    else:
        per_point(args)


if __name__ == "__main__":
    main()
