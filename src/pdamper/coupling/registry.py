"""Damper models by fidelity name, for the CLI and scenario files.

A new fidelity registers its class here; no caller branches on the name.
"""

from __future__ import annotations

from pdamper.coupling.analytical import AnalyticalDamper
from pdamper.coupling.base import DamperModel
from pdamper.coupling.dem import DEMDamper
from pdamper.errors import InputError

DAMPER_MODELS: dict[str, type[DamperModel]] = {
    AnalyticalDamper.fidelity: AnalyticalDamper,
    DEMDamper.fidelity: DEMDamper,
}


def get_damper_model(name: str, field: str = "damper") -> type[DamperModel]:
    """The damper model class of fidelity ``name``."""
    try:
        return DAMPER_MODELS[name]
    except KeyError:
        raise InputError(field, f"unknown or not yet available damper model {name!r}; "
                         f"available: {', '.join(DAMPER_MODELS)}") from None
