"""Damper models by fidelity name, for the CLI and scenario files.

A new fidelity registers its class here; no caller branches on the name.
"""

from __future__ import annotations

from pdamper.errors import InputError
from pdamper.models.analytical import AnalyticalDamper
from pdamper.models.base import DamperModel
from pdamper.models.dem import DEMDamper
from pdamper.models.fields import EffectiveFieldDamper
from pdamper.models.plastic import PlasticBedDamper

DAMPER_MODELS: dict[str, type[DamperModel]] = {
    AnalyticalDamper.fidelity: AnalyticalDamper,
    EffectiveFieldDamper.fidelity: EffectiveFieldDamper,
    DEMDamper.fidelity: DEMDamper,
    PlasticBedDamper.fidelity: PlasticBedDamper,
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


def _declared(field: str) -> str:
    """The field under which a model declares an input: a fitted curve's principal axis
    (``"restitution.particle_wall[pc1]"``) by its curve's field."""
    return field.partition("[")[0]


def input_users(field: str) -> list[str]:
    """The fidelities whose answers depend on the input ``field`` (those that do not
    declare it in :attr:`~pdamper.models.base.DamperModel.unused_inputs`), in the
    registry's order.

    >>> input_users("particles.friction")
    ['dem']
    """
    key = _declared(field)
    return [name for name, cls in DAMPER_MODELS.items() if key not in cls.unused_inputs]


def not_used(cls: type[DamperModel], fields) -> dict[str, dict]:
    """The inputs among ``fields`` that fidelity ``cls`` does not use: field ->
    ``{"fidelity", "reason", "used_by"}`` (:func:`input_users`), from the models'
    declarations."""
    out = {}
    for f in fields:
        why = cls.unused_inputs.get(_declared(f))
        if why is not None:
            out[f] = {"fidelity": cls.fidelity, "reason": why, "used_by": input_users(f)}
    return out
