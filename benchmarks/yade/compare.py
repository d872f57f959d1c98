"""pdamper against LIGGGHTS 3.8 *and* Yade on the same protocols: ``python
benchmarks/yade/compare.py --protocol lattice|random`` (the tables of docs/agreement.md,
"Yade, the second independent code").

The protocols are those of ``benchmarks/liggghts/agreement.py`` (its grid, jittered
lattices, cycles and windows, its LIGGGHTS and pdamper runs are reused as they are):

* ``lattice``: jitter seeds 1..N of ``jittered_lattice`` (the same positions in all three
  codes), settling, 8 cycles, cycles 3-8 averaged;
* ``random``: each code's own random packings (pdamper ``ParticleSet.random`` seeds
  0..N-1, LIGGGHTS ``fix insert/pack`` seeds ``PRIMES``, Yade ``makeCloud`` seeds 1..N),
  settling the free fall + 0.3 s (LIGGGHTS, Yade), 12 cycles, the last 8 averaged.

Yade: ``yade_damper.run_yade`` (Hertz-Mindlin with Tsuji's damping from the COR, step
0.5 ``PWaveTimeStep()``). pdamper: ``DEMDamper``'s default run from the same start, with
each ``--law``.

Every run is saved as soon as it ends, one JSON file per protocol and code
(``--results``, default ``benchmarks/yade/results/<protocol>_<code>.json``; a run
replaces the saved run of the same point, seed and law), and the table is printed from
the saved runs, so ``--codes pdamper`` reruns pdamper alone against the saved LIGGGHTS
and Yade runs, ``--codes none`` only prints the table. A run replaces only the runs it
makes: saved seeds beyond ``--seeds`` stay (the random table has four packings per code
at 20 Hz / 10 mm, 10 Hz / 32 mm and 20 Hz / 32 mm: rerun those with ``--seeds 4
--point ...``). One process at a time.

Judgement, per point, ``dev`` relative (to max(|value|, 0.05)), worst of eta and
m_eff/m_bed:

* lattice: a code's ``spread`` is the worst deviation between its jitters; LIGGGHTS and
  Yade **agree** where their worst paired (same jitter) deviation is within max(2 %, both
  spreads); there pdamper is **in** where its worst paired deviation from either code is
  within max(2 %, the codes' spreads, their deviation from each other).
* random: each code's ensemble mean and half-range; LIGGGHTS and Yade agree where their
  means are within max(5 %, the sum of their half-ranges); there pdamper is in where its
  mean is within max(5 %, its half-range + the two codes' pooled half-range) of the two
  codes' pooled mean.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "liggghts"))

import agreement as ag  # noqa: E402
import yade_damper  # noqa: E402

CODES = ("yade", "liggghts", "pdamper")
RANDOM_SETTLE = math.sqrt(2 * 0.12 / 9.81) + 0.3  # as agreement.py's LIGGGHTS random beds


def _key(r: dict) -> tuple:
    return (r["f"], r["x"], r["seed"], r.get("law"))


class Store:
    """The saved runs of one protocol and code (a JSON list of runs)."""

    def __init__(self, folder: Path, protocol: str, code: str):
        self.path = folder / f"{protocol}_{code}.json"
        self.runs = json.loads(self.path.read_text()) if self.path.exists() else []

    def put(self, run: dict) -> None:
        self.runs = [r for r in self.runs if _key(r) != _key(run)] + [run]
        self.runs.sort(key=lambda r: (r["f"], r["x"], r.get("law") or "", r["seed"]))
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.path.write_text(json.dumps(self.runs, indent=1) + "\n")

    def get(self, f: float, x: float, law: str | None = None) -> list:
        return [r for r in self.runs if r["f"] == f and r["x"] == x and r.get("law") == law]


def run_point(protocol: str, code: str, f: float, x: float, seed: int,
              law: str | None) -> dict:
    """One run of ``code`` at (f [Hz], x [mm]) from jitter ``seed`` (lattice) or its
    ``seed``-th random packing (1-based); eta, mass, cpu, steps."""
    lattice = protocol == "lattice"
    pos = ag.jittered_lattice(seed) if lattice else None
    cyc = {} if lattice else {"cycles": ag.RANDOM_CYCLES, "window": ag.RANDOM_WINDOW}
    if code == "liggghts":
        r = (ag.liggghts(f, x, positions=pos) if lattice else
             ag.liggghts(f, x, seed=ag.PRIMES[seed - 1], **cyc))
    elif code == "pdamper":
        r = (ag.pdamper_run(f, x, law, "default", positions=pos) if lattice else
             ag.pdamper_run(f, x, law, "default", seed=seed - 1, **cyc))
    else:
        y = (yade_damper.run_yade(f, x * 1e-3, positions=pos) if lattice else
             yade_damper.run_yade(f, x * 1e-3, seed=seed, cycles=ag.RANDOM_CYCLES,
                                  skip_cycles=ag.RANDOM_CYCLES - ag.RANDOM_WINDOW,
                                  settle_time=RANDOM_SETTLE))
        r = {"eta": y["loss_factor"], "mass": y["effective_mass_ratio"], "cpu": y["cpu"],
             "steps": y["steps"], "dt": y["dt"]}
    return {"f": f, "x": x, "seed": seed, "law": law if code == "pdamper" else None,
            **{k: (float(f"{v:.7g}") if isinstance(v, float) else v) for k, v in r.items()}}


def _worst(a: list, b: list) -> float:
    """Worst paired (same seed) relative deviation of eta and mass of runs ``a`` from ``b``."""
    bs = {r["seed"]: r for r in b}
    return max((max(abs(ag._dev(p["eta"], bs[p["seed"]]["eta"])),
                    abs(ag._dev(p["mass"], bs[p["seed"]]["mass"])))
                for p in a if p["seed"] in bs), default=math.nan)


def _spread(runs: list) -> float:
    return max((max(abs(ag._dev(p["eta"], q["eta"])), abs(ag._dev(p["mass"], q["mass"])))
                for p in runs for q in runs), default=math.nan)


def _vals(runs: list, q: str) -> str:
    return " / ".join(f"{r[q]:.3f}" for r in sorted(runs, key=lambda r: r["seed"])) or "-"


def _pct(v: float) -> str:
    return "-" if math.isnan(v) else f"{100 * v:.1f} %"


def lattice_table(points, stores, laws) -> tuple[str, dict]:
    """The lattice table (markdown) and its counts."""
    head = ("| point | LIGGGHTS eta | m_eff/m_bed | Yade eta | m_eff/m_bed | "
            "L-Y dev (allowed) | " + " | ".join(f"pdamper {law} eta | m_eff/m_bed | dev"
                                               for law in laws) + " |")
    lines = [head, "|" + "---|" * (6 + 3 * len(laws))]
    counts = {"agree": 0, "points": 0, **{law: 0 for law in laws}}
    for f, x in points:
        lg, yd = stores["liggghts"].get(f, x), stores["yade"].get(f, x)
        if not lg or not yd:
            continue
        counts["points"] += 1
        d_ly = _worst(yd, lg)
        spread = max(_spread(lg), _spread(yd))
        agree = d_ly <= max(0.02, spread)
        counts["agree"] += agree
        cells = [f"{f:g} Hz / {x:g} mm", _vals(lg, "eta"), _vals(lg, "mass"),
                 _vals(yd, "eta"), _vals(yd, "mass"),
                 f"{_pct(d_ly)} ({_pct(max(0.02, spread))})"
                 + (" agree" if agree else " **differ**")]
        for law in laws:
            pd = stores["pdamper"].get(f, x, law)
            dev = max(_worst(pd, lg), _worst(pd, yd)) if pd else math.nan
            mark = ""
            if pd and agree:
                inside = dev <= max(0.02, spread, d_ly)
                counts[law] += inside
                mark = " in" if inside else " **out**"
            cells += [_vals(pd, "eta"), _vals(pd, "mass"), _pct(dev) + mark]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines), counts


def _ens(runs: list, q: str) -> tuple[float, float]:
    return ag._stats([r[q] for r in runs])


def random_table(points, stores, laws) -> tuple[str, dict]:
    """The random-bed table (markdown, eta and m_eff/m_bed per code) and its counts."""
    law = laws[0]
    lines = ["| point | LIGGGHTS eta | Yade eta | pdamper eta | LIGGGHTS m_eff/m_bed | "
             "Yade m_eff/m_bed | pdamper m_eff/m_bed | L-Y dev (allowed) | pdamper dev "
             "from L+Y (allowed) |", "|---|---|---|---|---|---|---|---|---|"]
    counts = {"agree": 0, "points": 0, law: 0}

    def worst(pairs):  # (dev, allowed) of eta and of mass: the one nearer or past its limit
        return max(pairs, key=lambda p: p[0] - p[1])

    for f, x in points:
        lg, yd = stores["liggghts"].get(f, x), stores["yade"].get(f, x)
        pd = stores["pdamper"].get(f, x, law)
        if not lg or not yd:
            continue
        counts["points"] += 1
        ly, pl = [], []
        for q in ("eta", "mass"):
            (a, sa), (b, sb) = _ens(yd, q), _ens(lg, q)
            scale = max(abs(b), 0.05)
            ly.append((abs(ag._dev(a, b)), max(0.05, (sa + sb) / scale)))
            if pd:
                m, s = _ens(lg + yd, q)
                p, sp = _ens(pd, q)
                pl.append((abs(ag._dev(p, m)), max(0.05, (sp + s) / max(abs(m), 0.05))))
        d_ly, al_ly = worst(ly)
        agree = d_ly <= al_ly
        counts["agree"] += agree
        cells = [f"{f:g} Hz / {x:g} mm", _vals(lg, "eta"), _vals(yd, "eta"), _vals(pd, "eta"),
                 _vals(lg, "mass"), _vals(yd, "mass"), _vals(pd, "mass"),
                 f"{_pct(d_ly)} ({_pct(al_ly)})" + (" agree" if agree else " **differ**")]
        if pd:
            d_p, al_p = worst(pl)
            mark = ""
            if agree:
                counts[law] += d_p <= al_p
                mark = " in" if d_p <= al_p else " **out**"
            cells.append(f"{_pct(d_p)} ({_pct(al_p)})" + mark)
        else:
            cells.append("-")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines), counts


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--protocol", choices=["lattice", "random"], required=True)
    ap.add_argument("--seeds", type=int, default=2,
                    help="jitter seeds (lattice) or packings per code (random)")
    ap.add_argument("--codes", default=",".join(CODES),
                    help="codes to run, comma-separated (yade, liggghts, pdamper), or "
                    "'none': the others' runs are read from --results")
    ap.add_argument("--law", action="append", choices=["tsuji", "exact", "gonthier"],
                    help="pdamper's damping law (repeatable; default tsuji and exact for "
                    "the lattice, tsuji for random beds)")
    ap.add_argument("--point", type=float, nargs=2, action="append", metavar=("HZ", "MM"),
                    help="this point instead of the grid (repeatable)")
    ap.add_argument("--results", default=str(HERE / "results"),
                    help="folder of the saved runs (one JSON file per protocol and code)")
    args = ap.parse_args(argv)
    codes = [] if args.codes == "none" else args.codes.split(",")
    bad = [c for c in codes if c not in CODES]
    if bad or args.seeds < 1:
        ap.error(f"--codes: {', '.join(bad)} not in {', '.join(CODES)}" if bad
                 else "--seeds must be at least 1")
    laws = args.law or (["tsuji", "exact"] if args.protocol == "lattice" else ["tsuji"])
    if "yade" in codes and not yade_damper.available():
        sys.exit("yade not found (Debian: apt-get install yade)")
    if "liggghts" in codes:
        from liggghts_damper import available
        if not available():
            sys.exit("liggghts not found (Debian: apt-get install liggghts)")
    points = [tuple(p) for p in args.point] if args.point else ag.GRID
    folder = Path(args.results)
    stores = {c: Store(folder, args.protocol, c) for c in CODES}
    for f, x in points:
        for code in codes:
            for law in laws if code == "pdamper" else [None]:
                for seed in range(1, args.seeds + 1):
                    run = run_point(args.protocol, code, f, x, seed, law)
                    stores[code].put(run)
                    print(f"{f:>4g} Hz {x:>3g} mm {code:<8} {law or '':<6} seed {seed}: eta "
                          f"{run['eta']:.3f} m_eff/m_bed {run['mass']:.3f} ({run['cpu']:.1f} s "
                          f"CPU)", flush=True)
    table = lattice_table if args.protocol == "lattice" else random_table
    text, counts = table(points, stores, laws)
    print(text)
    print(f"LIGGGHTS and Yade agree at {counts['agree']} of {counts['points']} points; "
          "where they agree pdamper is in at " + ", ".join(
              f"{counts[law]} ({law})" for law in laws))


if __name__ == "__main__":
    main()
