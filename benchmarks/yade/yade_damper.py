"""Yade runs of pdamper's benchmark damper (Yade script: ``damper_yade.py`` beside this file).

:func:`run_yade` writes the parameters of one (f, X) point as JSON, runs ``yade -n -x
damper_yade.py PARAMS`` (one serial process) and applies the complex power method
(Eqs. 1-4, ``complex_power_of_windows`` of benchmarks/liggghts) to the mean force of the
particles on the container over each window, as for LIGGGHTS. :func:`impact_cor` runs one
normal impact and returns the COR Yade gives. Yade must be installed (Debian: ``apt-get
install yade``; checked with Yade 2023.02a).

The damper is the LIGGGHTS deck's (benchmarks/liggghts/damper.in): 32 steel spheres of
``PAPER_DAMPER`` in the PVC box 40 x 40 x 120 mm (six infinite walls, one rigid box,
given the harmonic velocity each step by ``HarmonicMotionEngine``), constant COR 0.6
(particle-particle) / 0.85 (particle-wall), mu 0.1, g 9.81 m/s^2, settling, then x_c = X
sin(2 pi f t). The law is Yade's Hertz-Mindlin (``Ip2_FrictMat_FrictMat_MindlinPhys``
with ``en = es`` the COR, ``Law2_ScGeom_MindlinPhys_Mindlin``): Hertz normal force,
Tsuji's damping ``2 sqrt(5/6) |ln e| / sqrt(ln^2 e + pi^2) sqrt(2 E* sqrt(R*)) sqrt(m*)
delta^(1/4)`` (the coefficient LIGGGHTS and pdamper's ``damping_model="tsuji"`` use), an
incremental Mindlin tangential spring with Coulomb limit and the same viscous coefficient
while sticking, no local damping.

**The wall's stiffness.** Yade's Hertz-Mindlin takes a wall as a sphere of the particle's
radius (R* = r / 2, where a half-space has R* = r: LIGGGHTS, pdamper). With ``wall=
"hertz"`` (default) the PVC's Young's modulus is raised so that Yade's E* sqrt(R*) of a
sphere-wall contact equals the half-space's (:func:`wall_young`: 4.27 GPa for 3 GPa):
the normal force and Tsuji's damping of the wall contacts are then those of the other
codes (the COR is the same either way: Tsuji's COR does not depend on the stiffness).
``wall="yade"`` keeps the PVC's 3 GPa (Yade's stock behaviour, a 29 % softer wall).
The tangential stiffness of a steel-PVC contact in Yade uses the mean shear modulus
(13x LIGGGHTS'; between two steel spheres the two are equal), which cannot be matched;
it acts only while a contact sticks.
"""

from __future__ import annotations

import json
import math
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parents[1] / "liggghts"))

from liggghts_damper import complex_power_of_windows  # noqa: E402

from pdamper.parameters import PAPER_DAMPER  # noqa: E402

SCRIPT = Path(__file__).with_name("damper_yade.py")
#: Yade's users' step: half the P-wave step ``PWaveTimeStep()`` (r / sqrt(E / rho) = 0.97 us
#: for these spheres), the fraction of most of Yade's examples; 0.09 Rayleigh times
STEP_FRACTION = 0.5


def available() -> bool:
    """True if the ``yade`` executable is on the path."""
    return shutil.which("yade") is not None


def pwave_step(damper=None) -> float:
    """Yade's ``PWaveTimeStep()`` of the damper's spheres [s]: r / sqrt(E / rho)."""
    d = damper or PAPER_DAMPER
    m = d.particle_material
    return d.particle_radius / math.sqrt(m.youngs_modulus / m.density)


def wall_young(damper=None, wall: str = "hertz") -> float:
    """The wall's Young's modulus [Pa] given to Yade: the PVC's (``wall="yade"``), or
    (``"hertz"``) the one that makes Yade's sphere-wall contact, R* = r / 2, as stiff as
    a sphere on a half-space, R* = r: E*' = sqrt(2) E*, solved for the wall's modulus."""
    d = damper or PAPER_DAMPER
    p, w = d.particle_material, d.wall_material
    if wall == "yade":
        return w.youngs_modulus
    if wall != "hertz":
        raise ValueError(f"wall: '{wall}' is not 'hertz' or 'yade'")
    cp = (1 - p.poisson_ratio ** 2) / p.youngs_modulus
    e_star = 1.0 / (cp + (1 - w.poisson_ratio ** 2) / w.youngs_modulus)
    return (1 - w.poisson_ratio ** 2) / (1.0 / (math.sqrt(2.0) * e_star) - cp)


def step(frequency: float, per_cycle: int = 400, step_fraction: float = STEP_FRACTION,
         damper=None) -> tuple[float, int]:
    """Yade's step [s] at ``frequency`` [Hz] and the steps of a force window:
    ``step_fraction`` of ``PWaveTimeStep()``, rounded down so that ``per_cycle`` windows of
    whole steps fill a cycle."""
    period = 1.0 / frequency
    nout = math.ceil(period / per_cycle / (step_fraction * pwave_step(damper)))
    return period / per_cycle / nout, nout


def _params(damper, wall, restitution_pp, restitution_pw, friction) -> dict:
    p, w = damper.particle_material, damper.wall_material
    return {"E_p": p.youngs_modulus, "nu_p": p.poisson_ratio, "rho_p": p.density,
            "E_w": wall_young(damper, wall), "nu_w": w.poisson_ratio, "rho_w": w.density,
            "epp": restitution_pp, "epw": restitution_pw, "mu": friction,
            "radius": damper.particle_radius}


def _yade(params: dict) -> tuple[dict, float, float]:
    """Run the Yade script on ``params``; its JSON answer, wall and CPU seconds."""
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        params = dict(params, out=str(tmp / "out.json"))
        (tmp / "params.json").write_text(json.dumps(params))
        cmd = ["yade", "-n", "-j", "1", "-x", str(SCRIPT), str(tmp / "params.json")]
        t0 = time.perf_counter()
        c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run(cmd, capture_output=True, text=True, errors="replace", cwd=tmp,
                              env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin",
                                   "HOME": str(tmp)})
        wall = time.perf_counter() - t0
        c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        out = tmp / "out.json"
        if proc.returncode != 0 or not out.exists():
            raise RuntimeError(f"Yade failed: {proc.stdout[-2000:]} {proc.stderr[-2000:]}")
        cpu = (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)
        return json.loads(out.read_text()), wall, cpu


def impact_cor(pair: str, velocity: float, restitution: float, *, wall: str = "hertz",
               step_fraction: float = STEP_FRACTION) -> float:
    """The COR of one normal impact in Yade at ``velocity`` [m/s] (relative), no gravity,
    no friction: ``pair`` "wall" (a sphere on the PVC floor) or "sphere" (two spheres
    head-on), the law's COR set to ``restitution`` for that pair."""
    d = PAPER_DAMPER
    p = _params(d, wall, restitution, restitution, 0.0)
    p.update(mode="impact", pair=pair, velocity=velocity,
             dt=step_fraction * pwave_step(d))
    return _yade(p)[0]["cor"]


def run_yade(frequency: float, amplitude: float, count: int = 32, cycles: int = 8,
             skip_cycles: int = 2, per_cycle: int = 400, restitution_pp: float = 0.6,
             restitution_pw: float = 0.85, friction: float = 0.1,
             settle_time: float | None = None, positions: np.ndarray | None = None,
             seed: int | None = None, wall: str = "hertz",
             step_fraction: float = STEP_FRACTION, force: str = "momentum") -> dict:
    """One Yade run of the benchmark damper at ``frequency`` [Hz], ``amplitude`` [m].

    The spheres start from ``positions`` [m] (default: pdamper's lattice) or, with
    ``seed``, from Yade's random cloud (``SpherePack.makeCloud``, no overlaps) in the box.
    They settle for ``settle_time`` (default as LIGGGHTS' lattice runs: the free fall from
    the lid + 0.05 s), then the box moves for ``cycles`` cycles. The step is
    ``step_fraction`` of ``PWaveTimeStep()``, rounded down so that ``per_cycle`` windows of
    whole steps fill a cycle. Returns the loss factor and effective mass ratio over
    cycles ``skip_cycles + 1 .. cycles``, the step, steps, wall and CPU seconds.
    ``force``: how the window means of the force on the container are taken: "forces"
    (``O.forces.f`` of the six walls summed every step, a Python call per step) or
    "momentum" (default: minus the spheres' momentum change over the window less
    gravity's impulse, the same sum read every window, about 2x cheaper).
    """
    from pdamper.dem.packing import lattice_layers

    d = PAPER_DAMPER.with_count(count)
    lz = d.box[2]
    if settle_time is None:
        settle_time = math.sqrt(2.0 * lz / 9.81) + 0.05
    period = 1.0 / frequency
    dt, nout = step(frequency, per_cycle, step_fraction, d)
    nrun = cycles * per_cycle * nout
    nsettle = round(settle_time / dt)
    if seed is None and positions is None:
        positions = lattice_layers(count, d.particle_radius, d.box)
    p = _params(d, wall, restitution_pp, restitution_pw, friction)
    p.update(mode="damper", box=list(d.box), count=count, g=9.81, dt=dt, nout=nout,
             nsettle=nsettle, nrun=nrun, amp=amplitude, freq=frequency,
             positions=None if positions is None else np.asarray(positions).tolist(),
             seed=-1 if seed is None else int(seed), force=force)
    res, wall_s, cpu = _yade(p)
    rows = np.array(res["windows"], dtype=float)
    t_hi = rows[:, 0] * dt
    t_lo = t_hi - nout * dt
    eta, ratio = complex_power_of_windows(t_lo, t_hi, rows[:, 1], frequency, amplitude,
                                          d.bed_mass, skip_cycles * period, cycles * period)
    return {"wall": wall_s, "cpu": cpu, "steps": nsettle + nrun, "dt": dt,
            "loss_factor": eta, "effective_mass_ratio": ratio,
            "box_z_end": res["box_z_end"], "box_z_expected": res["box_z_expected"]}
