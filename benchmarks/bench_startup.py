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
status 1 when a target is missed. The figures depend on the machine and on its load: the
load average is printed with them.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
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


def run_once(src: Path, args: list[str], python: str = sys.executable) -> float:
    """Wall time [s] of one process ``python *args`` with ``src`` on the path."""
    t0 = time.perf_counter()
    proc = subprocess.run([python, *args], env=_env(src), stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True, check=False)
    elapsed = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} with {src} ended with status "
                           f"{proc.returncode}: {proc.stderr.strip()[-500:]}")
    return elapsed


def dem_kernel_seconds(src: Path, python: str = sys.executable) -> float | None:
    """The DEM run's own wall time in the benchmark command (``--json``'s wall_seconds)."""
    proc = subprocess.run([python, *CASES[2][1], "--json"], env=_env(src), capture_output=True,
                          text=True, check=False)
    try:
        return float(json.loads(proc.stdout)["wall_seconds"])
    except (ValueError, KeyError, TypeError):
        return None


def measure(trees: dict[str, Path], repeat: int, python: str = sys.executable,
            progress=None) -> dict[str, dict[str, list[float]]]:
    """``times[case][tree]``: ``repeat`` wall times each, the trees taking turns."""
    times = {label: {name: [] for name in trees} for label, _, _ in CASES}
    for _label, args, _ in CASES:  # warm the caches (and compile a tree's kernels)
        for src in trees.values():
            run_once(src, args, python)
    for i in range(repeat):
        for label, args, _ in CASES:
            for name, src in trees.items():
                times[label][name].append(run_once(src, args, python))
        if progress:
            progress(i + 1, repeat)
    return times


def _fmt(ts: list[float]) -> str:
    return f"{statistics.median(ts):6.3f} s ({min(ts):.2f}-{max(ts):.2f})"


def table(times: dict[str, dict[str, list[float]]], trees: dict[str, Path]) -> tuple[str, bool]:
    """The table of medians (min-max) and whether every target is met by ``this``."""
    names = list(trees)
    head = f"{'command':32s} {'target':>7s}  " + "  ".join(f"{n:>24s}" for n in names)
    if "baseline" in trees:
        head += f"  {'speed-up':>8s}"
    lines = [head + "  met", "-" * (len(head) + 5)]
    ok = True
    for label, _, target in CASES:
        row = f"{label:32s} {target:6.2f}s  " + "  ".join(f"{_fmt(times[label][n]):>24s}"
                                                          for n in names)
        this = statistics.median(times[label]["this"])
        if "baseline" in trees:
            row += f"  {statistics.median(times[label]['baseline']) / this:7.1f}x"
        met = this <= target
        ok &= met
        lines.append(row + ("  yes" if met else "  NO"))
    return "\n".join(lines), ok


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
    times = measure(trees, args.repeat, args.python,
                    progress=lambda i, n: print(f"  round {i}/{n}", file=sys.stderr, flush=True))
    text, ok = table(times, trees)
    print(text)
    kernel = {name: dem_kernel_seconds(src, args.python) for name, src in trees.items()}
    print("DEM run itself in the dem command (its wall_seconds, one run): "
          + ", ".join(f"{n} {k:.3f} s" if k is not None else f"{n} n/a"
                      for n, k in kernel.items()))
    print("load average after " + " ".join(f"{x:.2f}" for x in os.getloadavg())
          + f"; benchmark took {time.perf_counter() - t0:.0f} s")
    return 0 if ok or not args.check else 1


if __name__ == "__main__":
    sys.exit(main())
