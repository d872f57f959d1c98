"""Bit-for-bit check of the DEM engine against another source tree (a refactoring's
baseline): nine short runs across the engine's paths, a SHA-256 of every result array.

The runs span velocity Verlet and Gear, the damping laws (``exact``, ``gonthier``,
``tsuji``), lattice and random-bed starts, a start from a settled bed, the ``auto``
integrator's hand-overs and probes, the transient tolerance, Gear with and without free
flights, a structure's and a prescribed motion, the step profile, runs in the smallest
chunks and a run ended by ``stop``. Every array and counter of each
:class:`~pdamper.dem.DEMResult` is hashed (the wall times excepted: they are the only
thing that may differ).

Run::

    python3 benchmarks/check_bit_identical.py                       # hashes of this tree
    python3 benchmarks/check_bit_identical.py --baseline-src OLD/src   # compare two trees

(``git worktree add ../pdamper-base <commit>`` gives such a tree.) Each tree runs in a
fresh ``python`` process with ``PYTHONPATH`` set to its ``src``; with ``--baseline-src``
the script ends with status 1 unless every run is identical. ``--json PATH`` writes the
hashes. The runs take a few seconds together once the kernels are compiled (a tree never
run before compiles them first: minutes).
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEFAULT_SRC = HERE.parent / "src"

#: Result fields left out of the hashes: wall times (the only thing allowed to differ).
WALL_FIELDS = ("wall_seconds", "settle_seconds", "kernel_seconds_per_sample")


def _inputs():
    """The benchmark damper's inputs (paper values), built inside the measured tree."""
    import numpy as np  # noqa: F401

    from pdamper.contact.restitution import ConstantRestitution
    from pdamper.dem import ContactParameters, Container, ParticleSet
    from pdamper.materials import PVC, S235
    from pdamper.parameters import vertical_dampers_paper as paper

    box = paper.PAPER_CONTAINER
    r = paper.PAPER_PARTICLE_RADIUS

    def contact(law: str) -> ContactParameters:
        return ContactParameters(ConstantRestitution(paper.BENCHMARK_RESTITUTION_PP),
                                 ConstantRestitution(paper.BENCHMARK_RESTITUTION_PW),
                                 paper.PAPER_FRICTION, paper.PAPER_FRICTION,
                                 damping_model=law)

    def lattice(n: int) -> ParticleSet:
        return ParticleSet.lattice(n, box, r, S235)

    def random(n: int, seed: int) -> ParticleSet:
        return ParticleSet.random(n, box, r, S235, seed=seed)

    return Container(box, PVC), contact, lattice, random


def runs() -> dict:
    """The nine runs: name -> a callable returning its DEMResult."""
    import numpy as np

    from pdamper.dem import DEMEngine, HarmonicMotion, PrescribedMotion, StructureMotion
    from pdamper.parameters import PAPER_STRUCTURE as S

    box, contact, lattice, random = _inputs()

    def eng(ps, law="exact", motion=None, **kw):
        # the engine's settings as one EngineSettings where the tree has them, else as the
        # keywords of the earlier engine (so one script compares both)
        try:
            from pdamper.dem import EngineSettings
        except ImportError:
            return DEMEngine(ps, box, contact(law), motion, **kw)
        return DEMEngine(ps, box, contact(law), motion, EngineSettings(**kw))

    def settled_start():
        a = eng(random(24, 5), "gonthier", motion=HarmonicMotion(0.02, 15.0),
                integrator="gear", settle_time=0.04)
        b = eng(random(24, 5), "gonthier", motion=HarmonicMotion(0.03, 12.0),
                integrator="gear", settle_time=0.04)
        return b.run(0.08, sample_rate=2000.0, start=a.settle())

    def stopped_profile():
        def stop(partial):
            return partial.simulated_time >= 2 / 20.0 - 1e-12
        return eng(lattice(16), "tsuji", motion=HarmonicMotion(0.01, 20.0), integrator="gear",
                   settle_time=0.02).run(5 / 20.0, sample_rate=2000.0, stop=stop,
                                         chunk_seconds=1e-9, step_profile=True)

    def prescribed():
        w = 2 * math.pi * 12.0
        m = PrescribedMotion(lambda t: 0.015 * np.sin(w * t) ** 3, sample_interval=1e-5)
        return eng(lattice(20), "exact", motion=m, integrator="verlet",
                   settle_time=0.03).run(0.03, sample_rate=3000.0, snapshot_rate=300.0)

    return {
        "verlet lattice exact harmonic": lambda: eng(
            lattice(32), "exact", motion=HarmonicMotion(0.032, 10.0), integrator="verlet",
            settle_time=0.03).run(0.03, sample_rate=2000.0, snapshot_rate=200.0),
        "gear lattice gonthier harmonic": lambda: eng(
            lattice(32), "gonthier", motion=HarmonicMotion(0.032, 10.0), integrator="gear",
            settle_time=0.05).run(0.1, sample_rate=2000.0),
        "gear random tsuji, no free flights, 1e-9 s chunks": lambda: eng(
            random(24, 3), "tsuji", motion=HarmonicMotion(0.02, 15.0), integrator="gear",
            settle_time=0.05, gear_free_flight=False).run(
            0.08, sample_rate=1500.0, snapshot_rate=500.0, chunk_seconds=1e-9),
        "verlet random gonthier structure": lambda: eng(
            random(24, 7), "gonthier", integrator="verlet", settle_time=0.03,
            motion=StructureMotion(mass=S.mass, damping=S.damping, stiffness=S.stiffness,
                                   x0=-0.058)).run(0.02, sample_rate=1500.0),
        "gear from a settled bed, free flights": settled_start,
        "auto hand-overs and probes": lambda: eng(
            lattice(32), "exact", motion=HarmonicMotion(0.032, 10.0), integrator="auto",
            settle_time=0.02, auto_cost_ratio=math.inf).run(0.03, sample_rate=2000.0,
                                                            chunk_seconds=1e-9),
        "gear transient tolerance": lambda: eng(
            lattice(32), "gonthier", motion=HarmonicMotion(0.01, 30.0), integrator="gear",
            settle_time=0.02, transient_cycles=2, gear_transient_tolerance=1e-4).run(
            0.1, sample_rate=4000.0),
        "gear tsuji stopped early, step profile, smallest chunks": stopped_profile,
        "verlet prescribed motion with snapshots": prescribed,
    }


def _digest(value) -> str:
    import numpy as np

    h = hashlib.sha256()
    if isinstance(value, np.ndarray):
        h.update(f"{value.dtype.str}{value.shape}".encode())
        h.update(np.ascontiguousarray(value).tobytes())
    else:
        h.update(json.dumps(value, sort_keys=True, default=repr).encode())
    return h.hexdigest()


def hashes(names=None) -> dict:
    """``{run: {"fields": {field: sha256}, "all": sha256, "seconds": wall}}`` in this
    process (the tree on ``sys.path``), of the runs ``names`` (default: all nine)."""
    out = {}
    for name, make in runs().items():
        if names is not None and name not in names:
            continue
        t0 = time.perf_counter()
        res = make()
        seconds = time.perf_counter() - t0
        fields = {f.name: _digest(getattr(res, f.name)) for f in dataclasses.fields(res)
                  if f.name not in WALL_FIELDS}
        total = hashlib.sha256("".join(fields[k] for k in sorted(fields)).encode()).hexdigest()
        out[name] = {"fields": fields, "all": total, "seconds": seconds,
                     "steps": int(res.steps)}
    return out


def in_tree(src: Path) -> dict:
    """:func:`hashes` of the tree ``src``, in a fresh process."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "hashes.json"
        env = dict(os.environ, PYTHONPATH=str(src))
        proc = subprocess.run([sys.executable, __file__, "--in-process", "--json", str(path)],
                              env=env, capture_output=True, text=True, check=False)
        if proc.returncode != 0:
            raise RuntimeError(f"the runs failed with {src}: {proc.stderr.strip()[-2000:]}")
        return json.loads(path.read_text())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline-src", type=Path, help="source tree to compare with")
    ap.add_argument("--src", type=Path, default=DEFAULT_SRC,
                    help="source tree measured (default: this checkout's src)")
    ap.add_argument("--json", type=Path, help="write the hashes here")
    ap.add_argument("--in-process", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.in_process:
        args.json.write_text(json.dumps(hashes(), indent=1))
        return 0
    this = in_tree(args.src.resolve())
    base = in_tree(args.baseline_src.resolve()) if args.baseline_src else None
    same = 0
    for name, h in this.items():
        line = f"{h['all'][:16]}  {h['steps']:>8d} steps {h['seconds']:6.2f} s  {name}"
        if base is not None:
            b = base.get(name)
            # a result field one tree lacks (added since) is listed, not compared
            common = [] if b is None else [k for k in h["fields"] if k in b["fields"]]
            new = [] if b is None else sorted(set(h["fields"]) ^ set(b["fields"]))
            diff = [k for k in common if h["fields"][k] != b["fields"][k]]
            ok = b is not None and not diff
            same += ok
            line += ("  identical" if ok else
                     f"  DIFFERENT ({', '.join(diff) if b is not None else 'missing'})")
            line += f" (fields of one tree only: {', '.join(new)})" if new else ""
        print(line)
    if args.json:
        args.json.write_text(json.dumps({"this": this, "baseline": base}, indent=1))
    if base is None:
        return 0
    print(f"{same}/{len(this)} identical to {args.baseline_src}")
    return 0 if same == len(this) == len(base) else 1


if __name__ == "__main__":
    sys.exit(main())
