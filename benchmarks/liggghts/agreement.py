"""Loss factor and effective mass of pdamper against LIGGGHTS 3.8 on the same protocol
(``python benchmarks/liggghts/compare.py --protocol lattice|random``; the tables of
docs/agreement.md).

* ``lattice`` (the paper's protocol): the 4 x 4 lattice of 32 spheres, every sphere moved
  vertically by a uniform jitter of +-0.02 mm (jitter seed k, the same positions in both
  codes; the layers lifted by 0.04 mm so that nothing overlaps: the 40 mm box holds four
  touching spheres across, so a horizontal jitter would start with overlaps), constant COR
  0.6 / 0.85, mu 0.1; settling, 8 cycles, complex power over cycles 3-8. pdamper runs as
  ``DEMDamper`` does by default from that bed (its Level II settling, Gear), with the
  damping law asked (``--law``), and with ``--converged`` converged (velocity Verlet at
  safety 0.005, from the first jitter). ``--friction spring`` runs pdamper with LIGGGHTS'
  tangential law (a spring with a Coulomb limit) instead of its tanh-regularised friction;
  its default run is then ``integrator = auto`` (velocity Verlet: Gear has no such law).
* ``random``: random packings, pdamper's (``ParticleSet.random``, seed k) and LIGGGHTS'
  (``fix insert/pack``, seed prime k); settling (LIGGGHTS: the free fall + 0.3 s), 12
  cycles, complex power over the last 8 (cycles 5-12). Each code's ensemble over
  ``--seeds`` packings.

Every run is one serial process (LIGGGHTS) or one thread (pdamper), one after the other.
"""

from __future__ import annotations

import json
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from liggghts_damper import run_liggghts  # noqa: E402

#: 12 points over 5-20 Hz x 10-80 mm
GRID = [(f, x) for f in (5.0, 10.0, 15.0, 20.0) for x in (10.0, 32.0, 80.0)]
JITTER = 2e-5          # [m], +- on every sphere's height
LATTICE_CYCLES, LATTICE_SKIP = 8, 2
RANDOM_CYCLES, RANDOM_WINDOW = 12, 8
#: primes > 10000 (LIGGGHTS' seeds), one per realisation
PRIMES = (10007, 10009, 10037, 10039, 10061, 10067, 10069, 10079)
CONVERGED_SAFETY = 0.005
LIGGGHTS_STEP = 1e-6   # the users' step (compare.py); 0.7 % from a 0.43 us step at 10 Hz / 32 mm


def jittered_lattice(seed: int, count: int = 32) -> np.ndarray:
    """The lattice with every sphere's height moved by U(-JITTER, JITTER) (seed ``seed``),
    the layers lifted by 2 JITTER so that no sphere overlaps a neighbour or the floor."""
    from pdamper.dem.packing import lattice_layers
    from pdamper.parameters import PAPER_DAMPER

    d = PAPER_DAMPER.with_count(count)
    pos = lattice_layers(count, d.particle_radius, d.box)
    layer = np.round((pos[:, 2] - d.particle_radius) / (2 * d.particle_radius))
    rng = np.random.default_rng(seed)
    pos[:, 2] += (2 * layer + 1) * JITTER + rng.uniform(-JITTER, JITTER, count)
    return pos


def pdamper_run(f: float, x_mm: float, law: str, kind: str, *, positions=None,
                seed: int = 0, cycles: int = LATTICE_CYCLES, window: int | None = None,
                friction: str = "regularised") -> dict:
    """One pdamper run: ``kind`` "default" (DEMDamper's defaults for the start it has) or
    "converged" (velocity Verlet at safety 0.005); from ``positions`` or, if None, the random
    packing of ``seed``. Loss factor and mass ratio over the last ``window`` cycles
    (default: all after the paper's 2). ``friction``: pdamper's tangential law,
    ``regularised`` (its default) or ``spring`` (LIGGGHTS' law; its default run is
    ``integrator = auto``, i.e. velocity Verlet at the default safety)."""
    from pdamper.dem import HarmonicMotion, ParticleSet
    from pdamper.models import DEMDamper
    from pdamper.parameters import PAPER_DAMPER

    d = PAPER_DAMPER.with_count(32)
    packing = "lattice" if positions is not None else "random"
    opts = {"integrator": "verlet", "safety": CONVERGED_SAFETY} if kind == "converged" else {}
    if friction != "regularised":
        opts = {"integrator": "auto", **opts, "friction_model": friction}
    model = DEMDamper(d, cycles=cycles, damping_model=law, packing=packing, seed=seed, **opts)
    ps = (ParticleSet(positions, d.particle_radius, d.particle_material)
          if positions is not None else model._particles()[1])
    eng = model._engine(ps, HarmonicMotion(x_mm * 1e-3, f), **model._level2_settling(),
                        **model._transient(packing))
    c0 = time.thread_time()
    res = eng.run(cycles / f, sample_rate=model.sample_rate)
    cpu = time.thread_time() - c0
    skip = cycles - window if window else LATTICE_SKIP
    cp = res.complex_power(skip)
    return {"eta": cp.loss_factor, "mass": cp.effective_mass_ratio, "cpu": cpu,
            "steps": int(res.steps)}


def liggghts(f: float, x_mm: float, *, positions=None, seed: int | None = None,
             cycles: int = LATTICE_CYCLES, window: int | None = None) -> dict:
    skip = cycles - window if window else LATTICE_SKIP
    settle = None if seed is None else math.sqrt(2 * 0.12 / 9.81) + 0.3  # a random bed: longer
    r = run_liggghts(f, x_mm * 1e-3, dt=LIGGGHTS_STEP, cycles=cycles, skip_cycles=skip,
                     positions=positions, insert_seed=seed, settle_time=settle)
    return {"eta": r["loss_factor"], "mass": r["effective_mass_ratio"], "cpu": r["cpu"],
            "steps": r["steps"]}


def _stats(values):
    m = statistics.fmean(values)
    return m, (max(values) - min(values)) / 2 if len(values) > 1 else 0.0


def _dev(a: float, b: float) -> float:
    return (a - b) / max(abs(b), 0.05)


def lattice_table(points, seeds: int, laws, out: Path | None, converged: bool = False,
                  friction: str = "regularised") -> list:
    """Per point: LIGGGHTS and pdamper (default and converged, each law, tangential law
    ``friction``) from the same jittered lattices; means and half-ranges over the jitter
    seeds."""
    rows = []
    for f, x in points:
        row = {"f": f, "x": x, "liggghts": [], "pdamper": {}}
        for k in range(1, seeds + 1):
            pos = jittered_lattice(k)
            row["liggghts"].append(liggghts(f, x, positions=pos))
            for law in laws:
                # the converged reference (20-60 s a run) only with --converged, first jitter
                for kind in ("default", "converged") if converged and k == 1 else ("default",):
                    row["pdamper"].setdefault(f"{_name(law, friction)} {kind}", []).append(
                        pdamper_run(f, x, law, kind, positions=pos, friction=friction))
        rows.append(row)
        _print_lattice_row(row)
        if out:
            out.write_text(json.dumps(rows, indent=1))
    return rows


def _name(law: str, friction: str) -> str:
    """A pdamper column's law: the damping law, ``+spring`` with the spring friction law."""
    return law if friction == "regularised" else f"{law}+{friction}"


def _print_lattice_row(row) -> None:
    lg = row["liggghts"]
    le, _ = _stats([r["eta"] for r in lg])
    lm, _ = _stats([r["mass"] for r in lg])
    parts = [f"{row['f']:>4g} Hz {row['x']:>3g} mm | LIGGGHTS eta "
             + "/".join(f"{r['eta']:.3f}" for r in lg) + " m "
             + "/".join(f"{r['mass']:.3f}" for r in lg)]
    for name, runs in row["pdamper"].items():
        e = [r["eta"] for r in runs]
        m = [r["mass"] for r in runs]
        worst = max(max(abs(_dev(a, b["eta"])), abs(_dev(c, b["mass"])))
                    # paired by jitter (a converged column has the first jitter only)
                    for a, c, b in zip(e, m, lg[:len(e)], strict=True))
        parts.append(f"{name}: eta " + "/".join(f"{v:.3f}" for v in e) + " m "
                     + "/".join(f"{v:.3f}" for v in m) + f" worst {100 * worst:.1f} % "
                     f"({sum(r['cpu'] for r in runs):.1f} s)")
    print(" | ".join(parts), f"(LIGGGHTS {sum(r['cpu'] for r in lg):.0f} s; means {le:.3f} "
          f"{lm:.3f})", flush=True)


def lattice_markdown(rows) -> str:
    """docs/agreement.md's lattice table: per point LIGGGHTS' eta and m_eff/m_bed (jitters
    1 / 2), pdamper's default with each law, and the worst paired deviation against the
    allowed max(2 %, LIGGGHTS' spread over the jitters)."""
    laws = [k.split()[0] for k in rows[0]["pdamper"] if k.endswith("default")]
    head = "| point | LIGGGHTS eta | m_eff/m_bed | spread | " + " | ".join(
        f"pdamper {law} eta | m_eff/m_bed | dev" for law in laws) + " |"
    lines = [head, "|" + "---|" * (4 + 3 * len(laws))]
    for row in rows:
        lg = row["liggghts"]
        spread = max(max(abs(_dev(a["eta"], b["eta"])), abs(_dev(a["mass"], b["mass"])))
                     for a in lg for b in lg)
        allowed = max(0.02, spread)
        cells = [f"{row['f']:g} Hz / {row['x']:g} mm",
                 " / ".join(f"{r['eta']:.3f}" for r in lg),
                 " / ".join(f"{r['mass']:.3f}" for r in lg), f"{100 * spread:.1f} %"]
        for law in laws:
            runs = row["pdamper"][f"{law} default"]
            worst = max(max(abs(_dev(p["eta"], q["eta"])), abs(_dev(p["mass"], q["mass"])))
                        for p, q in zip(runs, lg, strict=True))
            cells += [" / ".join(f"{r['eta']:.3f}" for r in runs),
                      " / ".join(f"{r['mass']:.3f}" for r in runs),
                      f"{100 * worst:.1f} %" + (" **out**" if worst > allowed else "")]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def random_markdown(rows) -> str:
    """docs/agreement.md's random-bed table: each code's ensemble (values per seed), the
    deviation of the means against the allowed max(5 %, combined half-ranges)."""
    lines = ["| point | LIGGGHTS eta | pdamper eta | dev (allowed) | LIGGGHTS m_eff/m_bed | "
             "pdamper m_eff/m_bed | dev (allowed) |", "|---|---|---|---|---|---|---|"]
    for row in rows:
        cells = [f"{row['f']:g} Hz / {row['x']:g} mm"]
        for q in ("eta", "mass"):
            a, sa = _stats([r[q] for r in row["pdamper"]])
            b, sb = _stats([r[q] for r in row["liggghts"]])
            dev = _dev(a, b)
            allowed = max(0.05, (sa + sb) / max(abs(b), 0.05))
            cells += [" / ".join(f"{r[q]:.3f}" for r in row["liggghts"]),
                      " / ".join(f"{r[q]:.3f}" for r in row["pdamper"]),
                      f"{100 * dev:+.1f} % ({100 * allowed:.0f} %)"
                      + (" **out**" if abs(dev) > allowed else "")]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def random_table(points, seeds: int, law: str, out: Path | None,
                 friction: str = "regularised") -> list:
    """Per point: the ensembles of ``seeds`` random packings of each code (pdamper's
    tangential law ``friction``)."""
    rows = []
    for f, x in points:
        lg = [liggghts(f, x, seed=PRIMES[k], cycles=RANDOM_CYCLES, window=RANDOM_WINDOW)
              for k in range(seeds)]
        pd = [pdamper_run(f, x, law, "default", seed=k, cycles=RANDOM_CYCLES,
                          window=RANDOM_WINDOW, friction=friction) for k in range(seeds)]
        row = {"f": f, "x": x, "liggghts": lg, "pdamper": pd}
        rows.append(row)
        cells = []
        ok = True
        for q in ("eta", "mass"):
            a, sa = _stats([r[q] for r in pd])
            b, sb = _stats([r[q] for r in lg])
            dev = _dev(a, b)
            allowed = max(0.05, (sa + sb) / max(abs(b), 0.05))
            ok &= abs(dev) <= allowed
            cells.append(f"{q} pdamper {a:.3f} +- {sa:.3f} LIGGGHTS {b:.3f} +- {sb:.3f} "
                         f"dev {100 * dev:+.1f} % (allowed {100 * allowed:.1f} %)")
        print(f"{f:>4g} Hz {x:>3g} mm | " + " | ".join(cells)
              + f" | {'ok' if ok else 'OUTSIDE'} | CPU pdamper "
              f"{sum(r['cpu'] for r in pd):.1f} s, LIGGGHTS {sum(r['cpu'] for r in lg):.0f} s",
              flush=True)
        if out:
            out.write_text(json.dumps(rows, indent=1))
    return rows


def main(args) -> None:
    points = GRID
    if args.point:
        points = [tuple(p) for p in args.point]
    out = Path(args.out) if args.out else None
    if args.protocol == "lattice":
        print(f"lattice + {JITTER * 1e3:g} mm jitter, {args.seeds} jitter seeds, cycles "
              f"{LATTICE_SKIP + 1}-{LATTICE_CYCLES}; LIGGGHTS (Tsuji law, tangential spring, "
              f"{LIGGGHTS_STEP * 1e6:g} us) against pdamper default / converged (Verlet at "
              f"{CONVERGED_SAFETY}), laws {', '.join(args.law)}, friction {args.friction}")
        print(lattice_markdown(lattice_table(points, args.seeds, args.law, out,
                                             args.converged, args.friction)))
    else:
        print(f"random packings, {args.seeds} seeds per code, {RANDOM_CYCLES} cycles, the "
              f"last {RANDOM_WINDOW} averaged; pdamper default ({args.law[0]} law, friction "
              f"{args.friction})")
        print(random_markdown(random_table(points, args.seeds, args.law[0], out,
                                           args.friction)))
