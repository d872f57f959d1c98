"""Start-up of pdamper as whole processes: ``import pdamper``, ``pdamper analytic`` and a
short DEM run, side by side with another source tree (the previous release).

Targets (median of 10 runs, warm caches: byte code, numba's kernels, pint's definitions;
``PYTHONDONTWRITEBYTECODE`` is ignored so that the byte code is cached as in an
installation):

=========================================================  ========
command                                                    target
=========================================================  ========
``python -c "import pdamper"``                             0.15 s
``pdamper analytic`` (the default point)                   0.4 s
``pdamper dem --frequency 10Hz --amplitude 32mm --cycles 8``  1.0 s
=========================================================  ========

Every command runs as a fresh ``python`` process with ``PYTHONPATH`` set to the source
tree measured (``pdamper ...`` as ``python -m pdamper ...``); the two trees take turns, run
by run, so that a change of the machine's load hits both alike. One unmeasured run of each
command first fills the caches (for a tree never run before this compiles its numba
kernels: minutes).

Run::

    python3 benchmarks/bench_startup.py --baseline-src /path/to/previous/release/src

(``git worktree add ../pdamper-base <commit>`` gives such a tree). ``--check`` ends with
status 1 when a target is missed; ``--liggghts`` also runs LIGGGHTS on the DEM case and
prints the whole-process ratio. The targets are wall times, which depend on the machine and
on its load: the load average is printed with them, and the CPU time (user + system) of
each process, which a loaded machine inflates less.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from datetime import UTC, datetime
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEFAULT_SRC = HERE.parent / "src"

#: (label, arguments after ``python``, target [s])
CASES = (
    ("import pdamper", ["-c", "import pdamper"], 0.15),
    ("pdamper analytic", ["-m", "pdamper", "analytic"], 0.4),
    ("pdamper dem 10Hz 32mm 8 cycles",
     ["-m", "pdamper", "dem", "--frequency", "10Hz", "--amplitude", "32mm", "--cycles", "8"],
     1.0),
)


def _env(src: Path) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(src)
    # warm: the byte code of the tree is written on the first run and read after, as an
    # installed package has it (pip compiles it)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def run_once(src: Path, args: list[str], python: str = sys.executable) -> tuple[float, float]:
    """Wall and CPU time [s] (user + system, ``getrusage``) of one process ``python *args``
    with ``src`` on the path."""
    c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([python, *args], env=_env(src), stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True, check=False)
    elapsed = time.perf_counter() - t0
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} with {src} ended with status "
                           f"{proc.returncode}: {proc.stderr.strip()[-500:]}")
    return elapsed, (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)


def dem_kernel_seconds(src: Path, python: str = sys.executable) -> float | None:
    """The DEM run's own wall time in the benchmark command (``--json``'s wall_seconds)."""
    proc = subprocess.run([python, *CASES[2][1], "--json"], env=_env(src), capture_output=True,
                          text=True, check=False)
    try:
        return float(json.loads(proc.stdout)["wall_seconds"])
    except (ValueError, KeyError, TypeError):
        return None


def measure(trees: dict[str, Path], repeat: int, python: str = sys.executable,
            progress=None) -> tuple[dict, dict]:
    """``(wall, cpu)``, each ``[case][tree]``: ``repeat`` times each, the trees taking
    turns."""
    wall = {label: {name: [] for name in trees} for label, _, _ in CASES}
    cpu = {label: {name: [] for name in trees} for label, _, _ in CASES}
    for _label, args, _ in CASES:  # warm the caches (and compile a tree's kernels)
        for src in trees.values():
            run_once(src, args, python)
    for i in range(repeat):
        for label, args, _ in CASES:
            for name, src in trees.items():
                w, c = run_once(src, args, python)
                wall[label][name].append(w)
                cpu[label][name].append(c)
        if progress:
            progress(i + 1, repeat)
    return wall, cpu


def _fmt(ts: list[float]) -> str:
    return f"{statistics.median(ts):6.3f} s ({min(ts):.2f}-{max(ts):.2f})"


def table(wall: dict, cpu: dict, trees: dict[str, Path]) -> tuple[str, bool]:
    """The table of wall-time medians (min-max) and CPU-time medians, and whether every
    target (wall) is met by ``this``."""
    names = list(trees)
    head = (f"{'command':32s} {'target':>7s}  " + "  ".join(f"{n + ' wall':>24s}" for n in names)
            + "  " + "  ".join(f"{n + ' CPU':>12s}" for n in names))
    if "baseline" in trees:
        head += f"  {'speed-up':>8s}"
    lines = [head + "  met", "-" * (len(head) + 5)]
    ok = True
    for label, _, target in CASES:
        row = (f"{label:32s} {target:6.2f}s  "
               + "  ".join(f"{_fmt(wall[label][n]):>24s}" for n in names) + "  "
               + "  ".join(f"{statistics.median(cpu[label][n]):10.3f} s" for n in names))
        this = statistics.median(wall[label]["this"])
        if "baseline" in trees:
            row += f"  {statistics.median(wall[label]['baseline']) / this:7.1f}x"
        met = this <= target
        ok &= met
        lines.append(row + ("  yes" if met else "  NO"))
    return "\n".join(lines), ok


def liggghts_single_run(src: Path, python: str = sys.executable) -> list[tuple[str, dict]]:
    """LIGGGHTS (``benchmarks/liggghts``) on the DEM case of the table: the benchmark damper
    at 10 Hz / 32 mm, settling and 8 cycles, one process each at the step LIGGGHTS users
    take (0.2 Rayleigh times) and at the step of pdamper's velocity Verlet there."""
    sys.path[:0] = [str(HERE / "liggghts"), str(src)]
    from liggghts_damper import available, run_liggghts

    if not available():
        return []
    code = ("from pdamper.dem import HarmonicMotion; from pdamper.models import DEMDamper; "
            "from pdamper.parameters import PAPER_DAMPER; "
            "e = DEMDamper(PAPER_DAMPER).build_engine(HarmonicMotion(0.032, 10.0)); "
            "print(e.time_step, e.rayleigh_time)")
    out = subprocess.run([python, "-c", code], env=_env(src), capture_output=True, text=True,
                         check=True).stdout.split()
    verlet_dt, t_r = float(out[-2]), float(out[-1])
    runs = []
    for label, dt in (("0.2 Rayleigh times", 0.2 * t_r), ("pdamper's Verlet step", verlet_dt)):
        runs.append((f"{label} ({dt * 1e6:.2f} us)",
                     run_liggghts(10.0, 0.032, count=32, dt=dt, cycles=8, skip_cycles=2)))
    return runs


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--src", type=Path, default=DEFAULT_SRC,
                    help="source tree measured (default: this checkout's src)")
    ap.add_argument("--baseline-src", type=Path, default=None,
                    help="source tree of the previous release, measured side by side")
    ap.add_argument("--repeat", type=int, default=10, help="runs per command and tree")
    ap.add_argument("--python", default=sys.executable, help="interpreter to run")
    ap.add_argument("--check", action="store_true", help="status 1 when a target is missed")
    ap.add_argument("--liggghts", action="store_true",
                    help="also run LIGGGHTS on the DEM case (one process per step) and print "
                         "the whole-process ratio")
    args = ap.parse_args(argv)
    trees = {"this": args.src.resolve()}
    if args.baseline_src is not None:
        trees = {"baseline": args.baseline_src.resolve(), **trees}
    for name, src in trees.items():
        if not (src / "pdamper" / "__init__.py").is_file():
            ap.error(f"{name}: no pdamper package in {src}")

    print(f"pdamper start-up, whole processes, median (min-max) of {args.repeat}, warm caches")
    print(f"date {datetime.now(UTC):%Y-%m-%d %H:%M} UTC; {platform.python_implementation()} "
          f"{platform.python_version()}; {os.cpu_count()} CPUs; load average before "
          + " ".join(f"{x:.2f}" for x in os.getloadavg()))
    for name, src in trees.items():
        print(f"  {name:8s} {src}")
    sys.stdout.flush()
    t0 = time.perf_counter()
    wall, cpu = measure(trees, args.repeat, args.python,
                        progress=lambda i, n: print(f"  round {i}/{n}", file=sys.stderr,
                                                    flush=True))
    text, ok = table(wall, cpu, trees)
    print(text)
    kernel = {name: dem_kernel_seconds(src, args.python) for name, src in trees.items()}
    print("DEM run itself in the dem command (its wall_seconds, one run): "
          + ", ".join(f"{n} {k:.3f} s" if k is not None else f"{n} n/a"
                      for n, k in kernel.items()))
    if args.liggghts:
        dem = CASES[2][0]
        runs = liggghts_single_run(trees["this"], args.python)
        if not runs:
            print("LIGGGHTS: not found (Debian: apt-get install liggghts)")
        for label, lg in runs:
            print(f"LIGGGHTS, same run, at {label}: {lg['wall']:.2f} s wall, {lg['cpu']:.2f} s "
                  "CPU; whole-process ratio to pdamper dem "
                  + ", ".join(f"{n} {lg['wall'] / statistics.median(wall[dem][n]):.1f}x wall, "
                              f"{lg['cpu'] / statistics.median(cpu[dem][n]):.1f}x CPU"
                              for n in trees))
    print("load average after " + " ".join(f"{x:.2f}" for x in os.getloadavg())
          + f"; benchmark took {time.perf_counter() - t0:.0f} s")
    return 0 if ok or not args.check else 1


if __name__ == "__main__":
    sys.exit(main())
