"""Bit-for-bit check of a run in a process that compiles the numba kernels against the
same run in a process that loads them from numba's cache.

Each run of :mod:`check_bit_identical` (all nine, or those named with ``--run``) is made
twice, each time in a fresh ``python`` process with ``NUMBA_CACHE_DIR`` pointed at one new,
empty directory: the first process compiles every kernel (cold cache, minutes), the
second loads them (warm cache, seconds). A SHA-256 of every result array is compared; the
script ends with status 1 unless every run is identical.

Run::

    python3 benchmarks/check_cold_compile.py                    # all nine runs
    python3 benchmarks/check_cold_compile.py --run "verlet lattice exact harmonic"
    python3 benchmarks/check_cold_compile.py --src OTHER/src    # another tree

Why this can differ at all: numba compiles a jitted function that does not set an option
(``fastmath``, ``error_model``) with the option of the function whose compilation first
needed it, and keeps one machine code per signature, in the cache too. A helper without
``fastmath`` called from a ``fastmath`` kernel is thus compiled with reassociation and
contraction allowed; the kernel then calls either its own inlined copy or the helper's
separately compiled one, depending on what was compiled or loaded first in the process,
and the two copies may round differently. The helpers of :mod:`pdamper.dem.kernels` set
their options explicitly (docs/performance.md: what is left); this script shows whether
the runs agree.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEFAULT_SRC = HERE.parent / "src"


def in_process(names, path: Path) -> None:
    """Hash the runs ``names`` in this process (the tree and cache from the environment)."""
    sys.path.insert(0, str(HERE))
    import check_bit_identical as cbi

    path.write_text(json.dumps(cbi.hashes(set(names) if names else None), indent=1))


def one_process(src: Path, cache: Path, names) -> tuple[dict, float]:
    """The hashes of the runs ``names`` in a fresh process on ``src`` with the numba cache
    ``cache``; and the process's wall time [s]."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "hashes.json"
        env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache))
        cmd = [sys.executable, __file__, "--in-process", "--json", str(out)]
        for n in names or ():
            cmd += ["--run", n]
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
        seconds = time.perf_counter() - t0
        if proc.returncode != 0:
            raise RuntimeError(f"the runs failed with {src}: {proc.stderr.strip()[-2000:]}")
        return json.loads(out.read_text()), seconds


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--src", type=Path, default=DEFAULT_SRC,
                    help="source tree measured (default: this checkout's src)")
    ap.add_argument("--run", action="append", default=[],
                    help="name of a run of check_bit_identical (repeatable; default: all)")
    ap.add_argument("--json", type=Path, help="write the hashes here")
    ap.add_argument("--in-process", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.in_process:
        in_process(args.run, args.json)
        return 0
    src = args.src.resolve()
    with tempfile.TemporaryDirectory(prefix="pdamper-numba-cache-") as cache:
        cold, t_cold = one_process(src, Path(cache), args.run)
        warm, t_warm = one_process(src, Path(cache), args.run)
    print(f"cold cache (compiles): {t_cold:.1f} s; warm cache (loads): {t_warm:.1f} s")
    same = 0
    for name, h in cold.items():
        w = warm.get(name)
        diff = [] if w is None else [k for k in h["fields"] if h["fields"][k] != w["fields"][k]]
        ok = w is not None and not diff and h["all"] == w["all"]
        same += ok
        print(f"{h['all'][:16]}  {name}  " + ("identical" if ok else
              f"DIFFERENT ({', '.join(diff) if w is not None else 'missing'})"))
    print(f"{same}/{len(cold)} identical, cold cache against warm cache")
    if args.json:
        args.json.write_text(json.dumps({"cold": cold, "warm": warm}, indent=1))
    return 0 if same == len(cold) and cold else 1


if __name__ == "__main__":
    sys.exit(main())
