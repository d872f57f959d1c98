"""What a report of a damper rests on: the inputs it used (and the others, each with why it
was not used), the structure's modal data and the load records embedded, the damping each
mode gains, in human units.

A report is archived and acted on: it must hold its data, not paths to them (a modes file
moves, a load record is edited), and it must not list values it did not use (the paper's
stiffness and damping beside a user's modes file read as if they mattered).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

#: Sections of the scenario that only the DEM reads.
_DEM_ONLY = ("dem", "restitution")


def used_inputs(inputs: dict, *, dem: bool = False,
                load_used: bool = False) -> tuple[dict, dict[str, str]]:
    """``(used, not_used)``: the scenario's inputs (``Scenario.model_dump(mode="json")``)
    that a report with (``dem``) or without the DEM used, and ``key -> why`` for every key
    left out (dotted keys; a whole section by its name). ``load_used``: the report's study
    ran the load history (an objective on the response to ``[load]``)."""
    used = {k: (dict(v) if isinstance(v, dict) else v) for k, v in inputs.items()}
    why: dict[str, str] = {}

    def drop(section: str, key: str | None, reason: str) -> None:
        if key is None:
            if section in used:
                del used[section]
                why[section] = reason
        elif section in used and key in used[section]:
            del used[section][key]
            why[f"{section}.{key}"] = reason

    s = inputs.get("structure", {})
    whole = "modes" if s.get("modes") else "beam" if s.get("beam") else None
    if whole is not None:
        for key in ("mass", "stiffness", "damping"):
            drop("structure", key, f"the structure is the {whole} "
                 f"({'the modes file' if whole == 'modes' else 'the Timoshenko beam'}), "
                 "not the 1-DOF of Eq. 23")
    if not dem:
        for section in _DEM_ONLY:
            drop(section, None, "read by the DEM only (report --dem)")
        drop("particles", "friction", "the analytical and field models do not use it; the "
             "DEM does (report --dem)")
        for key in ("dem_frequency", "dem_amplitude", "dem_packing"):
            drop("map", key, "the DEM map's grid (report --dem)")
    drop("simulation", "model", "the report runs every model it compares, not this one")
    o = inputs.get("optimization", {})
    objective = o.get("objective")
    if objective not in ("peak-frf", "rms-frf"):
        for key in ("band", "frf_load"):
            drop("optimization", key, f"the objective {objective!r} is not on the forced "
                 "response")
    if objective != "settling-time":
        drop("optimization", "threshold", "only settling-time has a threshold")
    if o.get("vary"):
        drop("optimization", "step", "the design variables are given (vary)")
    for key in ("workers", "scheduler"):
        drop("optimization", key, "the report's study runs in this process")
    if not load_used:
        drop("load", None, "no objective of the report runs a load history"
             if (inputs.get("load", {}).get("force") or
                 inputs.get("load", {}).get("base_acceleration")) else "no load given")
    for values in list(used.values()):  # a key not given (null) is not an input
        if isinstance(values, dict):
            for key in [k for k, v in values.items() if v is None]:
                del values[key]
    return used, why


def modal_data(structure: Any) -> dict:
    """The structure's data as a report holds them (SI): a 1-DOF's mass, stiffness,
    damping and natural frequency, or each mode's frequency, damping ratio and shapes at the
    damper's and the observation point, with the mass referred to the damper's point
    (1 / phi_d^2)."""
    if hasattr(structure, "stiffness") and hasattr(structure, "mass") \
            and not hasattr(structure, "frequencies"):
        return {"kind": "1-DOF", "mass": structure.mass, "stiffness": structure.stiffness,
                "damping": structure.damping,
                "natural_frequency": structure.natural_frequency,
                "damping_ratio": structure.damping_ratio,
                "units": {"mass": "kg", "stiffness": "N/m", "damping": "kg/s",
                          "natural_frequency": "Hz", "damping_ratio": "1"}}
    out_shape = (structure.output_shape if structure.output_shape is not None
                 else structure.damper_shape)
    modes = []
    for i, f in enumerate(structure.frequencies):
        phi = float(structure.damper_shape[i])
        modes.append({"mode": i + 1, "frequency": float(f),
                      "damping_ratio": float(structure.damping_ratios[i]),
                      "damper_shape": phi, "observation_shape": float(out_shape[i]),
                      "mass_at_damper": 1.0 / phi**2 if phi else math.inf})
    return {"kind": "modes", "modes": modes,
            "units": {"frequency": "Hz", "damping_ratio": "1", "damper_shape": "kg^-0.5",
                      "observation_shape": "kg^-0.5", "mass_at_damper": "kg"}}


def embedded_file(path: str | None) -> dict | None:
    """A data file's text, embedded (its name for the record): ``{"name", "text"}``; None
    without one."""
    if not path:
        return None
    p = Path(path)
    return {"name": p.name, "text": p.read_text(encoding="utf-8")}


def mode_damping(structure: Any, damper: Any, gravity: float) -> list[dict]:
    """The damping ratio each mode gains from the damper, at its optimal stroke X = h / pi
    (the most the analytical model gives it there): zeta_add,i = eta(f_i, X) m_bed
    phi_d,i^2 / 2, the damper's equivalent viscous damping d = E~ / (pi W X^2) = eta m_bed W
    (Eqs. 2-3) acting on mode i (mass-normalised, phi_d,i its shape at the damper; for a
    1-DOF phi^2 = 1 / M). Each row: ``mode``, ``frequency`` [Hz], ``damping_ratio`` (the
    structure's), ``added`` and ``total`` [-], ``stroke`` [m], ``loss_factor`` [-]."""
    from pdamper.models import AnalyticalDamper

    data = modal_data(structure)
    if data["kind"] == "1-DOF":
        rows = [(1, data["natural_frequency"], data["damping_ratio"],
                 1.0 / data["mass"])]
    else:
        rows = [(m["mode"], m["frequency"], m["damping_ratio"], m["damper_shape"] ** 2)
                for m in data["modes"]]
    out = []
    model = AnalyticalDamper(damper, gravity=gravity) if damper.count else None
    x = damper.optimal_stroke
    for mode, f, zeta, phi2 in rows:
        eta = 0.0 if model is None or x <= 0 else float(model.response(f, x).loss_factor)
        added = eta * damper.bed_mass * phi2 / 2.0
        out.append({"mode": mode, "frequency": f, "damping_ratio": zeta, "added": added,
                    "total": zeta + added, "stroke": x, "loss_factor": eta})
    return out


__all__ = ["embedded_file", "modal_data", "mode_damping", "used_inputs"]
