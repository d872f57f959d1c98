"""What decides the first cycle of Level III model 1 (docs/level3.md, "What decides model 1's
first cycle").

The paper's free decay (Sect. 4.2.1, Figs. 7/8): 32 spheres, structure released from
-58 mm, DEM coupled to Eq. (23) (model 1). For every variant the script runs model 1 for
0.95 s and prints, per run group (mean +- standard deviation over the realisations, min-max):

* ``zeta1``: damping ratio of the first cycle (release -> first minimum, Eqs. 24-25; it
  is the point "near 53 mm" of Fig. 8), ``zeta2``: of the second cycle;
* ``A(0.75)``: amplitude envelope at 0.75 s [mm];
* ``E1/E~``, ``E2/E~``: energy the bed dissipated in contacts (the DEM's ledger, normal +
  friction) over the first / second minimum-to-minimum cycle, over the analytical steady
  E~ (Eqs. 10/15) at that cycle's mean amplitude and frequency; ``W1/E~``: the work of the
  container on the bed over the first cycle (the energy the structure lost to the bed: it
  differs from E1 by what the bed holds as motion at the first minimum, or gave back);
* ``Ekin0``: the bed's kinetic energy at the release (after the settling) [J].

Reference lines: model 3 (analytical, steady loss factor from the first update on), its
first cycle in closed form with the steady E~, with a rigid plastic bed from rest and with
the lid impact only (the floor impact of the steady cycle falls after the first minimum),
the DEM's energy ledger over the first cycle, Level II DEM runs at the first cycle's
frequency and stroke started at mid-stroke and at the minimum (per-cycle dissipation and
work), and the no-particle decay of each structure.

Run: ``python benchmarks/level3_first_cycle.py [--quick] [--sections spread,ledger,...]``
(45 s of CPU, 1.5-2 min on a loaded 2-core machine; ``--quick``: fewer realisations, 22 s of
CPU). Seeds are explicit: jittered lattices use ``numpy.random.default_rng(seed)``, random
packings ``DEMDamper(seed=...)``. The runs are deterministic: a rerun prints the same table.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time

import numpy as np

from pdamper.analysis.analytical import bed_response
from pdamper.constants import STANDARD_GRAVITY
from pdamper.contact.restitution import ConstantRestitution
from pdamper.coupling import Simulation
from pdamper.models import AnalyticalDamper, DEMDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_INITIAL_DISPLACEMENT, PAPER_STRUCTURE
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.structure import SingleDOFStructure

#: Simulated time [s]: the negative peak after 0.75 s comes near 0.93 s, and the envelope
#: at 0.75 s interpolates between the peaks around it (FreeVibrationResult.amplitude_at).
DURATION = 0.95
#: Jitter of the lattice [m]: uniform in +-JITTER on every coordinate (a contact with a
#: side wall then overlaps by at most 1 um: 0.3 N for a moment, gone in the settling).
JITTER = 1e-6
X0 = PAPER_INITIAL_DISPLACEMENT


class JitteredLattice(DEMDamper):
    """The paper's 4 x 4 lattice with every coordinate moved by U(-jitter, jitter)."""

    def __init__(self, damper, jitter_seed: int, jitter: float = JITTER, **kw):
        super().__init__(damper, packing="lattice", **kw)
        self.jitter_seed, self.jitter = jitter_seed, jitter

    def _particles(self):
        kind, p = super()._particles()
        rng = np.random.default_rng(self.jitter_seed)
        p.positions = p.positions + rng.uniform(-self.jitter, self.jitter, p.positions.shape)
        return kind, p


def model(start: str, seed: int, damper=PAPER_DAMPER, jitter: float = JITTER, **kw):
    """``start``: "lattice" (exact), "jitter" (lattice + ``jitter``, ``seed``) or "random"."""
    if start == "jitter":
        return JitteredLattice(damper, seed, jitter, **kw)
    if start == "random":
        return DEMDamper(damper, packing="random", seed=seed, **kw)
    return DEMDamper(damper, packing="lattice", **kw)


def cycle_energy(run, n: int) -> tuple[float, float, float, float]:
    """(energy dissipated in contacts over minimum-to-minimum cycle n [J], work of the
    container on the bed over it, i.e. the energy the structure lost to the bed [J], that
    cycle's mean amplitude [m], its frequency [Hz])."""
    d = run.details
    e = d.dissipated_normal + d.dissipated_friction
    ta, tb = run.peak_times[n], run.peak_times[n + 1]
    de = float(np.interp(tb, d.time, e) - np.interp(ta, d.time, e))
    dw = float(np.interp(tb, d.time, d.container_work) - np.interp(ta, d.time, d.container_work))
    xm = 0.5 * (run.peak_amplitudes[n] + run.peak_amplitudes[n + 1])
    return de, dw, xm, 1.0 / (tb - ta)


def steady_energy(frequency: float, amplitude: float, damper=PAPER_DAMPER) -> float:
    """Analytical steady E~ per cycle [J] (Eqs. 10/15)."""
    return float(bed_response(frequency, amplitude, damper.clearance, damper.bed_mass)
                 .dissipated_energy_per_cycle)


def zeta_of(run, n: int) -> float:
    a = run.peak_amplitudes
    if len(a) <= n + 1:
        return float("nan")
    th = math.log(a[n] / a[n + 1])
    return th / math.sqrt(4 * math.pi**2 + th**2)


def measure(run, damper=PAPER_DAMPER) -> dict:
    out = {"zeta1": zeta_of(run, 0), "zeta2": zeta_of(run, 1),
           "A075": run.amplitude_at(paper.PAPER_COMPARISON_TIME) * 1e3,
           "Ekin0": float(run.details.kinetic_energy[0] + run.details.rotational_energy[0]),
           "cycles": run.damping_ratio}
    for n in (0, 1):
        de, dw, xm, f = cycle_energy(run, n)
        out[f"E{n + 1}/E~"] = de / steady_energy(f, xm, damper)
        out[f"W{n + 1}/E~"] = dw / steady_energy(f, xm, damper)
        out[f"X{n + 1}"] = xm * 1e3
    return out


def run_group(label: str, models, structure=PAPER_STRUCTURE, damper=PAPER_DAMPER,
              rows=None, say=print, x0: float = X0) -> list[dict]:
    res = []
    t0 = time.perf_counter()
    for m in models:
        r = Simulation(structure, m, x0).run(DURATION)
        res.append(measure(r, damper))
    rows.append((label, res))
    say(f"  {label}: {len(res)} runs, {time.perf_counter() - t0:.1f} s")
    return res


def per_cycle(label: str, vals, cycles: int = 4) -> str:
    """Mean zeta of each cycle over the runs, at the mean amplitude of that cycle."""
    k = min(cycles, min(len(v["cycles"][0]) for v in vals))
    amp = np.mean([v["cycles"][0][:k] for v in vals], axis=0)
    zeta = np.mean([v["cycles"][1][:k] for v in vals], axis=0)
    return (f"  {label}, zeta per cycle (mean): "
            + ", ".join(f"{z:.4f} at {a * 1e3:.1f} mm" for a, z in zip(amp, zeta, strict=True)))


COLUMNS = ("zeta1", "zeta2", "A075", "E1/E~", "W1/E~", "E2/E~", "Ekin0")
FMT = {"zeta1": "{:.4f}", "zeta2": "{:.4f}", "A075": "{:.1f}", "E1/E~": "{:.2f}",
       "W1/E~": "{:.2f}", "E2/E~": "{:.2f}", "Ekin0": "{:.0e}"}


def cell(vals, key) -> str:
    v = np.array([x[key] for x in vals], float)
    f = FMT[key]
    if len(v) == 1:
        return f.format(v[0])
    return (f"{f.format(v.mean())} +- {f.format(v.std(ddof=1))} "
            f"({f.format(v.min())}-{f.format(v.max())})")


def table(rows) -> str:
    head = ("| runs | n | zeta1 (first cycle) | zeta2 | A(0.75 s) [mm] | E1 / E~ | W1 / E~ "
            "| E2 / E~ | bed E_kin at release [J] |")
    lines = [head, "|" + "---|" * 9]
    for label, vals in rows:
        lines.append(f"| {label} | {len(vals)} | " + " | ".join(cell(vals, k) for k in COLUMNS)
                     + " |")
    return "\n".join(lines)


def analytical_lines(structure=PAPER_STRUCTURE, damper=PAPER_DAMPER) -> list[str]:
    """Model 3's run, and its first cycle with the lid impact only (the floor impact of the
    steady double collect-and-collide cycle falls after the first minimum)."""
    a = Simulation(structure, AnalyticalDamper(damper), X0).run(DURATION)
    z1, z2 = zeta_of(a, 0), zeta_of(a, 1)
    # Eq. (23) with the pseudo force over one cycle is linear: zeta = (D + d) / (2 sqrt(K M*))
    m = damper.bed_mass
    amp = abs(X0)
    f = float(a.effective_frequency[0]) if np.ndim(a.effective_frequency) else 5.45
    r = bed_response(f, amp, damper.clearance, m)
    w = 2 * math.pi * f
    m_eff = float(r.effective_mass_ratio) * m
    k, c = structure.stiffness, structure.damping
    mstar = structure.mass + m_eff
    d_full = float(r.dissipated_energy_per_cycle) / (math.pi * w * amp**2)
    e_top = 0.5 * m * float(r.relative_velocity_top) ** 2
    e_bot = 0.5 * m * float(r.relative_velocity_bottom) ** 2
    # the same rigid, perfectly plastic bed from rest: over the first cycle (minimum to
    # minimum) the structure loses the lid impact plus what the bed holds at the minimum
    # (released from the lid at the top-release phase, falling toward the floor)
    g = STANDARD_GRAVITY
    gam, hx = amp * w**2 / g, damper.clearance / amp
    p_tt, s = float(r.top_release_phase), 1.5 * math.pi - float(r.top_release_phase)
    y = math.sin(p_tt) + hx + math.cos(p_tt) * s - s**2 / (2 * gam)  # bed / X, container at -1
    v = math.cos(p_tt) - s / gam  # bed velocity / (X W)
    held = 0.5 * m * (v * amp * w) ** 2 + m * g * amp * (y + 1.0)
    w1 = e_top + held
    d_top = e_top / (math.pi * w * amp**2)
    d_w1 = w1 / (math.pi * w * amp**2)
    z_full = (c + d_full) / (2 * math.sqrt(k * mstar))
    z_top = (c + d_top) / (2 * math.sqrt(k * mstar))
    z_w1 = (c + d_w1) / (2 * math.sqrt(k * mstar))
    z_s = c / (2 * math.sqrt(k * structure.mass))
    phases = (f"take-off {float(r.takeoff_phase):.2f}, lid impact {float(r.top_impact_phase):.2f}, "
              f"floor impact {float(r.bottom_impact_phase):.2f} rad; minimum at "
              f"{1.5 * math.pi:.2f} rad")
    amp3, zeta3 = a.damping_ratio
    return [
        "model 3, zeta per cycle: " + ", ".join(
            f"{z:.4f} at {x * 1e3:.1f} mm" for x, z in zip(amp3[:4], zeta3[:4], strict=True)),
        f"model 3 (steady eta from the release on): zeta1 {z1:.4f}, zeta2 {z2:.4f}, "
        f"A(0.75 s) {a.amplitude_at(paper.PAPER_COMPARISON_TIME) * 1e3:.1f} mm",
        f"model 3's first cycle in closed form at {amp * 1e3:.0f} mm, {f:.2f} Hz: "
        f"zeta {z_full:.4f} with the steady E~ = {e_top + e_bot:.3f} J; "
        f"lid impact {e_top:.3f} J ({e_top / (e_top + e_bot):.0%}), floor impact "
        f"{e_bot:.3f} J; with the lid impact only: zeta {z_top:.4f}",
        f"rigid plastic bed from rest, first cycle: structure loses the lid impact + the "
        f"bed's energy at the minimum ({held:.3f} J, {(y + 1) * amp * 1e3:.0f} mm above the "
        f"floor) = {w1:.3f} J = {w1 / (e_top + e_bot):.2f} E~: zeta {z_w1:.4f}",
        f"steady double CaC phases at {amp * 1e3:.0f} mm: {phases}",
        f"no particles: zeta {z_s:.4f}, amplitude after 2 s "
        f"{amp * math.exp(-c / (2 * structure.mass) * 2.0) * 1e3:.1f} mm",
    ]


def level2_lines(frequency: float, amplitude: float, cycles: int, seeds) -> list[str]:
    """Level II DEM at the first cycle's frequency and stroke, from rest: the harmonic motion
    of Level II (``X sin W t``, from mid-stroke moving up) and the same motion started at
    its minimum (``-X cos W t``, as the free decay starts). Per cycle: the ledger's
    dissipation and the container's work on the bed, over the analytical steady E~."""
    from pdamper.dem import HarmonicMotion, PrescribedMotion

    w = 2 * math.pi * frequency
    e_ref = steady_energy(frequency, amplitude)
    eta = float(bed_response(frequency, amplitude, PAPER_DAMPER.clearance,
                             PAPER_DAMPER.bed_mass).loss_factor)
    from_minimum = PrescribedMotion(
        lambda t: -amplitude * np.cos(w * t), lambda t: amplitude * w * np.sin(w * t),
        lambda t: amplitude * w**2 * np.cos(w * t), sample_interval=1e-5)
    out = [f"Level II at {frequency:.2f} Hz / {amplitude * 1e3:.0f} mm: analytical E~ "
           f"{e_ref:.3f} J (eta {eta:.3f}); per cycle, over E~:"]
    for start, seed in seeds:
        for label, motion in (("X sin Wt", HarmonicMotion(amplitude, frequency)),
                              ("-X cos Wt", from_minimum)):
            res = model(start, seed).build_engine(motion).run(cycles / frequency,
                                                        sample_rate=200 * frequency)
            tb = np.arange(cycles + 1) / frequency
            diss = np.diff(np.interp(tb, res.time, res.dissipated_normal
                                     + res.dissipated_friction)) / e_ref
            work = np.diff(np.interp(tb, res.time, res.container_work)) / e_ref
            out.append(f"  {start} seed {seed}, {label}: dissipated "
                       + " ".join(f"{v:.2f}" for v in diss)
                       + "; container's work " + " ".join(f"{v:.2f}" for v in work)
                       + f"; cycles 3-{cycles}: {diss[2:].mean():.2f} / {work[2:].mean():.2f}")
    return out


def ledger_lines(start: str, seed: int) -> list[str]:
    """The first cycle as the DEM's ledger sees it, every 10 ms from 0.10 to 0.24 s: the
    structure's energy (1/2 K x^2 + 1/2 M v^2, x from its equilibrium without particles),
    the bed's kinetic energy, the energy dissipated so far, the bed's centre above the floor."""
    s = PAPER_STRUCTURE
    r = Simulation(s, model(start, seed), X0).run(0.25)
    d = r.details
    x, v = d.container_position, d.container_velocity
    e_s = 0.5 * s.stiffness * x**2 + 0.5 * s.mass * v**2
    e_d = d.dissipated_normal + d.dissipated_friction
    bed = d.center_of_mass[:, 2] - x
    out = [f"ledger, {start} seed {seed}: first minimum at {r.peak_times[1]:.3f} s"]
    for t in np.arange(0.10, 0.2401, 0.01):
        i = int(np.searchsorted(d.time, t))
        out.append(f"  t {d.time[i]:.3f} s  x {x[i] * 1e3:7.2f} mm  structure {e_s[i]:.3f} J  "
                   f"bed kinetic {d.kinetic_energy[i]:.3f} J  dissipated {e_d[i]:.3f} J  "
                   f"bed centre above the floor {bed[i] * 1e3:6.1f} mm")
    return out


def structures():
    """(label, structure): the default, the printed mass, masses at the measured 5.56 Hz,
    the FE beam's modal constants, and D = 0."""
    k, c = paper.PAPER_STIFFNESS, paper.PAPER_DAMPING
    w2 = (2 * math.pi * paper.PAPER_EIGENFREQUENCY) ** 2
    return [
        ("M 1.514 (default), K 1848, D 0.55", PAPER_STRUCTURE),
        ("M 1.139 (printed), K 1848: 6.41 Hz", SingleDOFStructure(1.139, c, k)),
        ("M 1.139, K 1390: 5.56 Hz", SingleDOFStructure(1.139, c, 1.139 * w2)),
        ("M 1.885, K 2300: 5.56 Hz (FE modal mass)", SingleDOFStructure(1.885, c, 1.885 * w2)),
        ("M 1.514, K 1848, D 0", SingleDOFStructure(paper.PAPER_MASS, 0.0, k)),
    ]


SECTIONS = ("spread", "ledger", "settle", "cor", "friction", "numerics", "play", "structure",
            "modes", "level2")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer realisations (about a third of the runs)")
    ap.add_argument("--sections", default=",".join(SECTIONS),
                    help=f"comma-separated subset of {','.join(SECTIONS)}")
    args = ap.parse_args(argv)
    n = 3 if args.quick else 8
    n_small = 2 if args.quick else 4
    sections = set(args.sections.split(","))
    if not sections <= set(SECTIONS):
        ap.error(f"--sections: unknown {', '.join(sorted(sections - set(SECTIONS)))}; "
                 f"known: {', '.join(SECTIONS)}")
    rows: list = []
    say = print
    t_all = time.perf_counter()

    for line in analytical_lines():
        say(line)
    if "spread" in sections:
        say("realisation spread")
        run_group("lattice (exact)", [model("lattice", 0)], rows=rows)
        run_group(f"lattice + {JITTER * 1e6:.0f} um jitter, seeds 0-{n - 1}",
                  [model("jitter", s) for s in range(n)], rows=rows)
        run_group(f"random packings, seeds 0-{n - 1}",
                  [model("random", s) for s in range(n)], rows=rows)
        for label, vals in rows[-3:]:
            say(per_cycle(label, vals))
        run_group(f"lattice + 20 um jitter, seeds 0-{n_small - 1}",
                  [model("jitter", s, jitter=2e-5) for s in range(n_small)], rows=rows)
    if "ledger" in sections:
        for start in ("jitter", "random"):
            for line in ledger_lines(start, 0):
                say(line)
    if "settle" in sections:
        say("settling")
        for st in (0.5, 1.2):
            for start in ("jitter", "random"):
                run_group(f"{start}, settle {st} s (default 0.21 s), seeds 0-{n_small - 1}",
                          [model(start, s, settle_time=st) for s in range(n_small)], rows=rows)
        # x0 is measured from the equilibrium without particles; the experiment's 58 mm were
        # most likely measured from its rest position with the bed in the box
        x_eq = -PAPER_DAMPER.bed_mass * STANDARD_GRAVITY / PAPER_STRUCTURE.stiffness
        run_group(f"random, released 58 mm below the loaded equilibrium (x0 = "
                  f"{(X0 + x_eq) * 1e3:.1f} mm), seeds 0-{n_small - 1}",
                  [model("random", s) for s in range(n_small)], rows=rows, x0=X0 + x_eq)
    if "cor" in sections:
        say("COR (the lattice's default 0.6/0.85 is in the first rows)")
        variants = [(f"COR {pp}/{pw}", PAPER_DAMPER.with_restitution(
            ConstantRestitution(pp), ConstantRestitution(pw)))
            for pp, pw in ((0.1, 0.1), (0.3, 0.5), (0.9, 0.95))]
        variants.insert(2, ("COR paper's curves (reconstructed)", PAPER_DAMPER.with_restitution(
            paper.PAPER_COR_PP, paper.PAPER_COR_PW)))
        for label, d in variants:
            for start in ("jitter", "random"):
                run_group(f"{start}, {label}, seeds 0-{n_small - 1}",
                          [model(start, s, damper=d) for s in range(n_small)], damper=d,
                          rows=rows)
    if "friction" in sections:
        say("friction")
        for mu in (0.0, 0.3, 0.5):
            d = dataclasses.replace(PAPER_DAMPER, friction=mu)
            for start in ("jitter", "random"):
                run_group(f"{start}, mu {mu}, seeds 0-{n_small - 1}",
                          [model(start, s, damper=d) for s in range(n_small)], damper=d,
                          rows=rows)
    if "numerics" in sections:
        say("integration and damping law")
        for label, kw in (("Gear tolerance 1e-6 (default 1e-5)", {"gear_tolerance": 1e-6}),
                          ("Tsuji damping law (default exact)", {"damping_model": "tsuji"})):
            for start in ("jitter", "random"):
                run_group(f"{start}, {label}, seeds 0-{n_small - 1}",
                          [model(start, s, **kw) for s in range(n_small)], rows=rows)
    if "play" in sections:
        say("play: the box 0.5 mm wider and deeper than four diameters")
        d = dataclasses.replace(PAPER_DAMPER, width=0.0405, depth=0.0405)
        for start in ("jitter", "random"):
            run_group(f"{start}, box 40.5 x 40.5 mm, seeds 0-{n_small - 1}",
                      [model(start, s, damper=d) for s in range(n_small)], damper=d, rows=rows)
    if "structure" in sections:
        say("structure")
        for label, s in structures()[1:]:
            run_group(f"random, {label}, seeds 0-{n_small - 1}",
                      [model("random", q) for q in range(n_small)], structure=s, rows=rows)
            lines = analytical_lines(s)
            for line in lines[1:4] + lines[-1:]:
                say(f"  {label}: {line}")
    if "modes" in sections:
        # the DEM couples to one mode only: the higher bending modes the release excites are
        # judged with model 3 on the FE beam (docs/structure.md), 1 against N modes
        from pdamper.parameters import paper_beam
        from pdamper.structure.modal import ModalStructure

        say("higher beam modes (model 3 on the FE beam, 6.09 Hz, zeta 0.0052 per mode)")
        beam, tip = paper_beam()
        for n_modes in (1, 3, 5):
            st = ModalStructure.from_beam(beam, tip, modes=n_modes, damping_ratio=0.0052)
            a = Simulation(st, AnalyticalDamper(PAPER_DAMPER), X0).run(DURATION)
            say(f"  {n_modes} mode(s): zeta1 {zeta_of(a, 0):.4f}, zeta2 {zeta_of(a, 1):.4f}, "
                f"A(0.75 s) {a.amplitude_at(paper.PAPER_COMPARISON_TIME) * 1e3:.2f} mm")
    if "level2" in sections:
        say("Level II at the first cycle's point")
        seeds = [("jitter", 0), ("random", 0)] + ([] if args.quick else [("random", 1)])
        for line in level2_lines(5.25, 0.053, 6 if args.quick else 12, seeds):
            say(line)
    say("")
    say(table(rows))
    say(f"\ntotal {time.perf_counter() - t_all:.0f} s")


if __name__ == "__main__":
    main()
