"""LIGGGHTS 3.8 runs of the benchmark damper (deck: ``damper.in`` beside this file).

:func:`run_liggghts` writes the container mesh (STL) and the initial lattice (the same
``pdamper.dem.packing.lattice_layers`` positions as pdamper's ``packing="lattice"``), runs
``stdbuf -o0 -e0 liggghts -in damper.in`` with the variables of one (f, X) point, and
applies the complex power method (Eqs. 1-4) to the force that LIGGGHTS reports on the
container mesh. LIGGGHTS must be installed (Debian: ``apt-get install liggghts``).
"""

from __future__ import annotations

import math
import resource
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from pdamper.dem.packing import lattice_layers
from pdamper.parameters import PAPER_DAMPER

DECK = Path(__file__).with_name("damper.in")


def available() -> bool:
    """True if the ``liggghts`` executable is on the path."""
    return shutil.which("liggghts") is not None


def _write_stl(path: Path, box) -> None:
    lx, ly, lz = box
    c = [(x, y, z) for z in (0.0, lz) for y in (0.0, ly) for x in (0.0, lx)]
    # the six faces as corner indices (two triangles each)
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    lines = ["solid box"]
    for a, b, cc, d in faces:
        for tri in ((a, b, cc), (a, cc, d)):
            p = np.array([c[k] for k in tri])
            nrm = np.cross(p[1] - p[0], p[2] - p[0])
            nrm /= np.linalg.norm(nrm)
            lines.append(f"facet normal {nrm[0]:g} {nrm[1]:g} {nrm[2]:g}")
            lines.append("outer loop")
            lines += [f"vertex {x:.9g} {y:.9g} {z:.9g}" for x, y, z in p]
            lines += ["endloop", "endfacet"]
    lines.append("endsolid box")
    path.write_text("\n".join(lines) + "\n")


def complex_power_of_windows(t_lo, t_hi, fz, frequency, amplitude, m_bed, ta, tb):
    """Loss factor and effective mass ratio (Eqs. 1-4) of window means ``fz`` of the force
    of the particles on the container over ``[t_lo, t_hi]`` windows inside ``[ta, tb]``,
    for ``x_c = X sin(W t)``: ``F* = 2/T sum_k F_k int_window exp(-i W t) dt`` (exact for
    window means), V* = X W, A* = i X W^2, driving force = -(force on the container)."""
    w = 2.0 * math.pi * frequency
    eps = 1e-9 / frequency
    keep = (t_lo >= ta - eps) & (t_hi <= tb + eps)
    ints = (np.exp(-1j * w * t_hi[keep]) - np.exp(-1j * w * t_lo[keep])) / (-1j * w)
    span = t_hi[keep][-1] - t_lo[keep][0]
    f_drive = 2.0 / span * np.sum(-fz[keep] * ints)
    v = amplitude * w
    a = 1j * amplitude * w * w
    e_diss = 0.5 * (f_drive * np.conj(v)).real / w   # E~ / (2 pi) with E~ = 2 pi/W Re P*
    return float(e_diss / (0.5 * m_bed * v * v)), float(abs(f_drive / a) / m_bed)


def run_liggghts(frequency: float, amplitude: float, count: int = 32, dt: float = 4e-7,
                 cycles: int = 8, skip_cycles: int = 2, per_cycle: int = 400,
                 restitution_pp: float = 0.6, restitution_pw: float = 0.85,
                 friction: float = 0.1, tangential: str = "history",
                 settle_time: float | None = None, block: int = 6,
                 positions: np.ndarray | None = None, insert_seed: int | None = None) -> dict:
    """One LIGGGHTS run of the benchmark damper at ``frequency`` [Hz], ``amplitude`` [m].

    The step is rounded so that ``per_cycle`` force windows of whole steps fill a cycle.
    Returns the wall and CPU time of the whole LIGGGHTS process (``wall``, ``cpu``), the
    steps, the loss factor and effective mass ratio over cycles ``skip_cycles + 1 ..
    cycles``, and the loss factor of consecutive blocks of ``block`` cycles (stationarity).

    The spheres start from ``positions`` [m] (default: pdamper's lattice), or with
    ``insert_seed`` (a prime > 10000, LIGGGHTS' rule) from a random packing that LIGGGHTS'
    ``fix insert/pack`` places in the box (non-overlapping, seeded), which then settles for
    ``settle_time`` like the lattice.
    """
    d = PAPER_DAMPER.with_count(count)
    box = d.box
    lz = box[2]
    if settle_time is None:  # as pdamper's DEMEngine default
        settle_time = math.sqrt(2.0 * lz / 9.81) + 0.05
    period = 1.0 / frequency
    nout = max(1, round(period / per_cycle / dt))
    dt = period / per_cycle / nout
    nrun = cycles * per_cycle * nout
    nsettle = round(settle_time / dt)
    pos = lattice_layers(count, d.particle_radius, box) if positions is None else positions
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        _write_stl(tmp / "box.stl", box)
        if insert_seed is None:
            atoms = "".join(f"create_atoms 1 single {x:.12g} {y:.12g} {z:.12g} units box\n"
                            for x, y, z in pos)
            atoms += f"set group all density 7900 diameter {2 * d.particle_radius:.12g}\n"
        else:  # a random packing: inserted at the first step of the settling run
            r = d.particle_radius
            atoms = (
                f"fix pts all particletemplate/sphere 15485863 atom_type 1 density constant "
                f"7900 radius constant {r:.12g}\n"
                f"fix pdd all particledistribution/discrete 32452843 1 pts 1.0\n"
                f"region ins block {r:.12g} {box[0] - r:.12g} {r:.12g} {box[1] - r:.12g} "
                f"{r:.12g} {lz - r:.12g} units box\n"
                f"fix ins all insert/pack seed {insert_seed} distributiontemplate pdd "
                f"insert_every once overlapcheck yes all_in yes particles_in_region {count} "
                f"region ins\n")
        (tmp / "atoms.in").write_text(atoms)
        out = tmp / "force.txt"
        var = {"dt": f"{dt:.12g}", "nsettle": nsettle, "nrun": nrun, "nout": nout,
               "amp": f"{amplitude:.12g}", "period": f"{period:.12g}",
               "epp": restitution_pp, "epw": restitution_pw, "mu": friction,
               "zlo": -amplitude - 0.01, "zhi": lz + amplitude + 0.01, "tangential": tangential,
               "stl": tmp / "box.stl", "atoms": tmp / "atoms.in", "out": out}
        cmd = ["stdbuf", "-o0", "-e0", "liggghts", "-in", str(DECK), "-log", str(tmp / "log")]
        for k, v in var.items():
            cmd += ["-var", k, str(v)]
        t0 = time.perf_counter()
        c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run(cmd, capture_output=True, text=True, errors="replace", cwd=tmp)
        wall = time.perf_counter() - t0
        c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)
        if proc.returncode != 0 or not out.exists():
            raise RuntimeError(f"LIGGGHTS failed: {proc.stdout[-2000:]} {proc.stderr[-2000:]}")
        if insert_seed is not None and f"inserted {count} particle" not in proc.stdout:
            raise RuntimeError(f"LIGGGHTS inserted fewer than {count} spheres: "
                               f"{proc.stdout[-2000:]}")
        data = np.loadtxt(out, comments="#")
    step, fz = data[:, 0], data[:, 1]
    # window k covers the excitation steps (k - 1) nout + 1 .. k nout
    t_hi = (step - nsettle) * dt
    t_lo = t_hi - nout * dt
    m_bed = d.bed_mass

    def cp(c0, c1):
        eta, ratio = complex_power_of_windows(t_lo, t_hi, fz, frequency, amplitude, m_bed,
                                              c0 * period, c1 * period)
        return eta, ratio

    eta, ratio = cp(skip_cycles, cycles)
    blocks = [round(cp(c, c + block)[0], 4) for c in range(skip_cycles, cycles - block + 1, block)]
    return {"wall": wall, "cpu": cpu, "steps": nsettle + nrun, "dt": dt,
            "loss_factor": eta, "effective_mass_ratio": ratio, "blocks": blocks,
            "us_per_step": 1e6 * wall / (nsettle + nrun),
            "simulated": nrun * dt}
