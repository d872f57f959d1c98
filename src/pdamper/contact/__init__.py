"""Level I: the contact law of the DEM (paper Sect. 3, "Discrete element method").

- :mod:`pdamper.contact.hertz`: Hertz normal stiffness, contact duration, Rayleigh time.
- :mod:`pdamper.contact.damping`: the damping parameter of the force law
  ``K delta^n (1 + d delta_dot)`` from a coefficient of restitution: the exact closed form
  (default) and Gonthier's approximation (the paper's choice).
- :mod:`pdamper.contact.restitution`: velocity-dependent coefficient-of-restitution curves.
"""
