"""Physical constants used across pdamper (SI units).

Each constant has one home here; models take gravity as an argument with this default so
that a user can change it for one run without touching module state.
"""

from __future__ import annotations

#: Standard gravity g [m/s^2]. The paper does not state its value; 9.81 m/s^2 reproduces its
#: X_min = g / w^2 = 8.8 mm (Sect. 4.2.1) and its Fig. 5 line A = g.
STANDARD_GRAVITY = 9.81

__all__ = ["STANDARD_GRAVITY"]
