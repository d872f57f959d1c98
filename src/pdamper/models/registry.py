"""Damper models by fidelity name, for the CLI and scenario files.

A new fidelity registers its class here; no caller branches on the name.
"""

from __future__ import annotations

from pdamper.errors import InputError
from pdamper.models.analytical import AnalyticalDamper
from pdamper.models.base import DamperModel
from pdamper.models.dem import DEMDamper
from pdamper.models.fields import EffectiveFieldDamper

DAMPER_MODELS: dict[str, type[DamperModel]] = {
    AnalyticalDamper.fidelity: AnalyticalDamper,
    EffectiveFieldDamper.fidelity: EffectiveFieldDamper,
    DEMDamper.fidelity: DEMDamper,
}


def get_damper_model(name: str, field: str = "model") -> type[DamperModel]:
    """The damper model class of fidelity ``name``.

    >>> get_damper_model("analytic").__name__
    'AnalyticalDamper'
    """
    try:
        return DAMPER_MODELS[name]
    except (KeyError, TypeError):
        raise InputError(field, f"unknown damper model {name!r}; available: "
                         f"{', '.join(DAMPER_MODELS)}") from None
