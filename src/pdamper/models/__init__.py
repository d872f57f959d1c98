"""Damper models: one interface, several fidelities (Level II, used by Level III).

Every fidelity is a :class:`DamperModel` subclass that answers :meth:`DamperModel.response`
under harmonic excitation with a :class:`DamperResponse`; the model's own details (the
analytical bed response, the DEM runs) travel inside that response. The Level III coupling
strategies (:mod:`pdamper.coupling`) run any of them on a structure, chosen by the model's
``coupling`` name. A new fidelity is a new subclass registered in :mod:`pdamper.models.registry`.

- :class:`AnalyticalDamper` (``"analytic"``, the paper's model 3): Eqs. (5)-(22).
- :class:`EffectiveFieldDamper` (``"fields"``, the paper's model 2): effective fields
  (a ``pdamper map``) interpolated in frequency and stroke.
- :class:`DEMDamper` (``"dem"``, the paper's model 1): the discrete element method.
- :class:`PlasticBedDamper` (``"plastic"``): the analytical bed integrated event by event as
  one perfectly plastic block, on the structure itself (any container motion).
"""

from pdamper.models.analytical import AnalyticalDamper
from pdamper.models.base import DamperModel, DamperResponse
from pdamper.models.dem import DEMDamper
from pdamper.models.fields import EffectiveFieldDamper
from pdamper.models.plastic import PlasticBedDamper
from pdamper.models.registry import DAMPER_MODELS, get_damper_model

__all__ = ["AnalyticalDamper", "DAMPER_MODELS", "DEMDamper", "DamperModel", "DamperResponse",
           "EffectiveFieldDamper", "PlasticBedDamper", "get_damper_model"]
