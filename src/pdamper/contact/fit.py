"""Fit a COR curve to measured points, with the uncertainty of its parameters (Level I).

:func:`fit_restitution` fits a curve of one fit family, a key of :data:`FIT_MODELS`
(Thornton's elastic-plastic model, the exponential and the linear forms of
:mod:`pdamper.contact.restitution`) by weighted
least squares (:func:`scipy.optimize.curve_fit`) and returns a :class:`RestitutionFit`: the
fitted curve, the parameters, their covariance and standard errors, and a confidence band.

Uncertainty: with the standard deviation of each point given (``std``, e.g. from repeated
drops), the covariance is that of the weighted least-squares estimate for those absolute
errors (``absolute_sigma=True``); without, the residual scatter sets the scale (the
covariance is multiplied by the reduced chi-square). The band at a velocity is the linear
(delta-method) propagation of the covariance through the fitted curve.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdamper.contact.restitution import (
    ExponentialRestitution,
    LinearRestitution,
    ParametricRestitution,
)
from pdamper.contact.thornton import ThorntonRestitution
from pdamper.errors import InputError

#: Models that can be fitted, by name.
FIT_MODELS: dict[str, type[ParametricRestitution]] = {
    "thornton": ThorntonRestitution,
    "exponential": ExponentialRestitution,
    "linear": LinearRestitution,
}


@dataclass(frozen=True)
class RestitutionFit:
    """A fitted COR curve.

    Attributes
    ----------
    model
        The fit family (a key of :data:`FIT_MODELS`).
    curve
        The fitted curve (usable by the DEM like any other).
    parameters
        Parameter names.
    values
        Fitted values (units: ``curve.UNITS``).
    covariance
        Covariance of the values.
    velocity, restitution, std
        The data [m/s], [-], [-] (``std`` None if not given).
    absolute_sigma
        True if the covariance rests on the given ``std``; False if on the residual scatter.
    """

    model: str
    curve: ParametricRestitution
    parameters: tuple[str, ...]
    values: np.ndarray
    covariance: np.ndarray
    velocity: np.ndarray
    restitution: np.ndarray
    std: np.ndarray | None
    absolute_sigma: bool
    extra: dict = field(default_factory=dict, compare=False)

    @property
    def uncertainty(self) -> np.ndarray:
        """Standard errors of the parameters (square roots of the covariance diagonal)."""
        return np.sqrt(np.diag(self.covariance))

    @property
    def residuals(self) -> np.ndarray:
        """Measured minus fitted COR at the data points [-]."""
        return self.restitution - self.curve(self.velocity)

    @property
    def chi2_reduced(self) -> float:
        """Reduced chi-square (with ``std``; else the residual variance) [-]."""
        dof = max(len(self.velocity) - len(self.values), 1)
        w = 1.0 if self.std is None else 1.0 / np.asarray(self.std) ** 2
        return float(np.sum(w * self.residuals**2) / dof)

    def band(self, v, k: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
        """``(lower, upper)`` COR at speeds ``v`` [m/s]: the fit plus/minus ``k`` standard
        errors of the model value (delta method with a central-difference Jacobian)."""
        v = np.atleast_1d(np.asarray(v, float))
        p = np.asarray(self.values, float)
        fun = self.curve.function
        fixed = self._fixed()
        jac = np.empty((v.size, p.size))
        for i in range(p.size):
            h = 1e-6 * max(abs(p[i]), 1e-6)
            up, dn = p.copy(), p.copy()
            up[i] += h
            dn[i] -= h
            jac[:, i] = (fun(v, *up, *fixed) - fun(v, *dn, *fixed)) / (2 * h)
        sd = np.sqrt(np.einsum("ij,jk,ik->i", jac, self.covariance, jac))
        e = self.curve(v)
        return e - k * sd, e + k * sd

    def curve_at(self, params) -> ParametricRestitution:
        """The curve of this fit family with parameters ``params`` (e.g. a sample of their
        uncertainty) for the same data; :class:`~pdamper.errors.InputError` where they
        give no valid COR (outside (0, 1])."""
        p = tuple(float(x) for x in np.asarray(params, float))
        if len(p) != len(self.parameters) or not all(np.isfinite(p)):
            raise InputError("restitution.fit", f"expected {len(self.parameters)} finite "
                             f"parameters {self.parameters}, got {p}")
        return type(self.curve).from_fit(p, self.velocity, name=getattr(self.curve, "name", ""))

    def _fixed(self) -> tuple:
        return (self.curve.v_hold,) if isinstance(self.curve, LinearRestitution) else ()

    def as_dict(self) -> dict:
        """JSON-ready summary."""
        return {"model": self.model, "curve": self.curve.describe(),
                "parameters": {n: {"value": float(x), "std": float(s), "unit": u}
                               for n, x, s, u in zip(self.parameters, self.values,
                                                     self.uncertainty, self.curve.UNITS,
                                                     strict=True)},
                "absolute_sigma": self.absolute_sigma, "chi2_reduced": self.chi2_reduced,
                "points": int(len(self.velocity))}


def fit_restitution(velocity, restitution, std=None, model: str = "exponential",
                    p0=None, name: str = "") -> RestitutionFit:
    """Fit a COR curve of the fit family ``model`` to points ``(velocity [m/s], restitution [-])``.

    Parameters
    ----------
    velocity, restitution
        The data; at least one point more than the fit family has parameters.
    std
        Standard deviation of each COR [-] (optional): weights, and the absolute scale of
        the parameter uncertainty.
    model
        The fit family: ``"thornton"`` (V_y), ``"exponential"`` (e0, e_inf, v_c) or ``"linear"`` (e0, slope;
        held beyond the highest measured speed).
    p0
        Starting values (default: the fit family's guess from the data).

    Examples
    --------
    >>> import numpy as np
    >>> v = np.linspace(0.05, 2.0, 12)
    >>> e = ExponentialRestitution(0.95, 0.5, 0.3)(v)
    >>> fit = fit_restitution(v, e, model="exponential")
    >>> [round(float(x), 6) for x in fit.values]
    [0.95, 0.5, 0.3]
    """
    from scipy.optimize import curve_fit

    if model not in FIT_MODELS:
        raise InputError("restitution.fit", f"must be one of {', '.join(FIT_MODELS)}, got {model!r}")
    cls = FIT_MODELS[model]
    v = np.asarray(velocity, float)
    e = np.asarray(restitution, float)
    s = None if std is None else np.asarray(std, float)
    npar = len(cls.PARAMETERS)
    if v.ndim != 1 or v.shape != e.shape or v.size < npar + 1:
        raise InputError("restitution.fit", f"the {model} model has {npar} parameter(s) and "
                         f"needs at least {npar + 1} points, got {v.size}")
    if not (np.all(np.isfinite(v)) and np.all(np.isfinite(e))):
        raise InputError("restitution.fit", "velocities and CORs must be finite")
    if s is not None and (s.shape != v.shape or np.any(~(s > 0))):
        raise InputError("restitution.fit", "std must give one value > 0 per point")
    guess = cls.guess(v, e) if p0 is None else tuple(p0)
    lo, hi = cls.BOUNDS
    guess = tuple(float(np.clip(g, a, b)) for g, a, b in zip(guess, lo, hi, strict=True))
    fixed = (float(np.max(v)),) if cls is LinearRestitution else ()

    def f(x, *p):
        return cls.function(x, *p, *fixed)

    try:
        popt, pcov = curve_fit(f, v, e, p0=guess, sigma=s, absolute_sigma=s is not None,
                               bounds=(lo, hi), maxfev=20000)
    except (RuntimeError, ValueError) as exc:
        raise InputError("restitution.fit", f"the {model} fit did not converge: {exc}") from None
    if not np.all(np.isfinite(pcov)):
        raise InputError("restitution.fit", f"the {model} model's parameters are not determined "
                         "by these points (infinite covariance); use more points or another model")
    try:
        curve = cls.from_fit(tuple(popt), v, name=name)
    except InputError as exc:
        raise InputError("restitution.fit", f"the fitted {model} curve is no COR: "
                         f"{exc.message}") from None
    return RestitutionFit(model, curve, cls.PARAMETERS, np.asarray(popt), np.asarray(pcov), v, e,
                          s, s is not None)


__all__ = ["FIT_MODELS", "RestitutionFit", "fit_restitution"]
