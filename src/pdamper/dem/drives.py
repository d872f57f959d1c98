"""The container motion of a DEM run as the kernels see it, and as the results record it.

:func:`excitation_drive` turns a motion of :mod:`pdamper.dem.inputs` (harmonic, table, a
1-DOF structure or a structure of N modes) into the kernels' :class:`~pdamper.dem.kernels.
state.Drive` bundle over the excitation's :class:`SampleGrid`; :func:`describe_motion` gives
the motion's inputs as plain values for :meth:`pdamper.dem.simulation.DEMEngine.describe`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pdamper.dem.inputs import (
    HarmonicMotion,
    ModalStructureMotion,
    PrescribedMotion,
    StructureMotion,
)
from pdamper.dem.kernels import state as K

Motion = HarmonicMotion | PrescribedMotion | StructureMotion


@dataclass(frozen=True)
class SampleGrid:
    """Sampling of the excitation phase."""

    duration: float
    interval: float           # sample interval [s]
    nsamp: int
    snap_every: int
    per_cycle: int            # samples per excitation cycle (harmonic motion), else 0
    frequency: float | None
    snapshots_requested: bool


_EMPTY = np.zeros(2)


def drive(kind: int, z0: float = 0.0, amplitude: float = 0.0, omega: float = 0.0,
          table_dt: float = 1.0,
          table: tuple[np.ndarray, np.ndarray, np.ndarray] = (_EMPTY, _EMPTY, _EMPTY),
          mass: float = 1.0, damping: float = 0.0, stiffness: float = 0.0,
          loaded: bool = False) -> K.Drive:
    """The kernels' motion bundle of ``kind`` (``K.MOTION_*``): position ``z0`` [m] (the
    phase [rad] of a structure's harmonic load), ``amplitude`` [m or N] at ``omega``
    [rad/s], tables of step ``table_dt`` [s], a 1-DOF structure's ``mass`` [kg],
    ``damping`` [N s/m], ``stiffness`` [N/m]."""
    return K.Drive(int(kind), float(z0), float(amplitude), float(omega), float(table_dt),
                   *table, float(mass), float(damping), float(stiffness), int(loaded))


def modal_drive(m: ModalStructureMotion, grid: SampleGrid) -> K.Drive:
    """The kernels' bundle of a structure of N modes (:mod:`pdamper.dem.kernels.modes`),
    its state at the motion's start (``q0``, ``qd0``; the base at rest at 0)."""
    n = m.modes
    w = m.angular_frequencies
    if m.loaded:
        h, zb, vb, fe, ab = m.modal_tables(grid.duration + 2 * grid.interval)
        base = dict(table_dt=h, table=(zb, vb, fe), loaded=True)
    else:  # a harmonic load rides on the harmonic fields, as for the 1-DOF
        ab = np.zeros(2)
        base = dict(amplitude=m.force_amplitude, omega=2.0 * math.pi * m.force_frequency,
                    z0=m.force_phase)
    one = drive(K.MOTION_STRUCTURE, mass=m.mass, damping=m.damping, stiffness=m.stiffness,
                **base)
    state = np.zeros((3, n))
    state[0] = m.q0
    state[1] = m.qd0
    weight = np.maximum(np.abs(m.damper_shape), np.abs(m.load_shape))
    return one._replace(
        nmodes=n, m_w2=np.ascontiguousarray(w * w),
        m_c=np.ascontiguousarray(2.0 * m.damping_ratios * w),
        m_phi=np.ascontiguousarray(m.damper_shape), m_load=np.ascontiguousarray(m.load_shape),
        m_gamma=np.ascontiguousarray(m.participation), m_weight=np.ascontiguousarray(weight),
        table_b=np.ascontiguousarray(ab, dtype=float), m_state=state,
        m_nord=np.zeros((6, n)), m_backup=np.zeros((6, n)),
        m_samples=np.zeros((grid.nsamp, 3 * n)))


def excitation_drive(m: Motion, grid: SampleGrid) -> K.Drive:
    """The kernels' bundle of the motion ``m`` over the excitation ``grid`` (its tables
    cover the duration and two sample intervals more)."""
    if isinstance(m, HarmonicMotion):
        return drive(K.MOTION_HARMONIC, amplitude=m.amplitude, omega=m.angular_frequency)
    if isinstance(m, PrescribedMotion):
        _, tz, tv, ta = m.table(grid.duration + 2 * grid.interval)
        return drive(K.MOTION_TABLE, table_dt=m.sample_interval, table=(tz, tv, ta))
    if isinstance(m, ModalStructureMotion):
        return modal_drive(m, grid)
    if m.loaded:
        h, zb, vb, fe = m.load_tables(grid.duration + 2 * grid.interval)
        return drive(K.MOTION_STRUCTURE, table_dt=h, table=(zb, vb, fe), mass=m.mass,
                     damping=m.damping, stiffness=m.stiffness, loaded=True)
    # a harmonic load rides on the harmonic fields (amplitude [N], omega, phase)
    return drive(K.MOTION_STRUCTURE, mass=m.mass, damping=m.damping, stiffness=m.stiffness,
                 amplitude=m.force_amplitude, omega=2.0 * math.pi * m.force_frequency,
                 z0=m.force_phase)


def describe_motion(m: Motion) -> dict:
    """The inputs of the motion ``m`` as plain values, keys with their SI unit
    (``amplitude_m``, ``structure_stiffness_n_m``, ...); a prescribed table adds none."""
    d: dict = {}
    if isinstance(m, HarmonicMotion):
        d.update(amplitude_m=m.amplitude, frequency_hz=m.frequency)
    elif isinstance(m, StructureMotion):
        d.update(structure_mass_kg=m.mass, structure_damping_kg_s=m.damping,
                 structure_stiffness_n_m=m.stiffness, structure_x0_m=m.x0,
                 structure_v0_m_s=m.v0)
        if m.force_amplitude > 0:
            d.update(structure_force_n=m.force_amplitude,
                     structure_force_frequency_hz=m.force_frequency,
                     structure_force_phase_rad=m.force_phase)
        for name, unit in (("force", "n"), ("base_acceleration", "m_s2")):
            rec = getattr(m, name)
            if rec is not None:  # the load history: its step and samples
                d.update({f"structure_{name}_step_s": rec[0],
                          f"structure_{name}_samples": int(rec[1].size),
                          f"structure_{name}_peak_{unit}": float(np.max(np.abs(rec[1])))})
        if isinstance(m, ModalStructureMotion):
            d.update(structure_modes=m.modes,
                     structure_frequencies_hz=(m.angular_frequencies
                                               / (2.0 * math.pi)).tolist())
    return d
