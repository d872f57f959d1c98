"""Propagation of input uncertainty to a damper's answers by quasi-Monte Carlo sampling.

An uncertain input (:class:`UncertainInput`) is a nominal value with a *standard
deviation*; its distribution is the normal of that mean and standard deviation truncated to
the input's valid range (a friction coefficient >= 0, a length > 0): the usual reading of
"0.1 +- 0.03" for a measured or toleranced quantity, and never a sample outside what the
models accept. (A tolerance band +-t read as three standard deviations is ``sd = t / 3``.)

:func:`propagate` draws the inputs with a scrambled Sobol' sequence
(:class:`scipy.stats.qmc.Sobol`, seeded; the seed is recorded) in the two matrices A and B
of Saltelli's design (2 d columns of one sequence, Saltelli et al. 2010, Sect. 5) and the d
matrices AB^(i) (A with input i taken from B): ``n (d + 2)`` evaluations for ``d`` inputs
and ``n`` base points. The answers' mean, standard deviation and percentiles are those of
the ``2 n`` points of A and B (each a QMC sample of the joint distribution); the first-order
and total Sobol' indices are Saltelli's (2010) and Jansen's (1999) estimators
(:func:`scipy.stats.sobol_indices`, ``method="saltelli_2010"``) on the same evaluations,
with bootstrap confidence intervals.

Why Sobol' indices rather than one-at-a-time: the answers are strongly nonlinear in the
inputs (the loss factor changes motion mode with the clearance; the landscape is flat near
the optimum), so a derivative at the nominal point can rank the inputs wrongly; the
variance-based indices take the whole distribution and the interactions (total index), and
they reuse the samples that give the band. The input that drives an answer's spread most
is the one with the largest total index.

Correlated inputs (a fitted curve's parameters, :class:`ParameterFit`) enter as
independent standard normals along the principal axes of their covariance
(:class:`FitAxis`), truncated to the box of valid curves; the answers then also carry, per
curve, the sums of its axes' indices (:attr:`AnswerSpread.groups`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pdamper.errors import InputError

#: Percentiles reported with every answer [%].
PERCENTILES = (5.0, 25.0, 50.0, 75.0, 95.0)
#: Base points of the Sobol' design: a power of two (the balance of the sequence).
MIN_POINTS, MAX_POINTS = 4, 65536
#: Confidence level of the bootstrap intervals of the indices.
CONFIDENCE = 0.95
#: Bootstrap resamples of those intervals.
N_RESAMPLES = 300


@dataclass(frozen=True)
class UncertainInput:
    """An input with a standard deviation: normal, truncated to ``[low, high]``.

    Attributes
    ----------
    field
        The input's name, e.g. ``"particles.friction"``.
    value
        Nominal value (the mean before truncation), SI.
    sd
        Standard deviation before truncation, SI, > 0.
    low, high
        Valid range (truncation); ``-inf``/``inf`` for none.
    unit
        SI unit, for the record.
    """

    field: str
    value: float
    sd: float
    low: float = -math.inf
    high: float = math.inf
    unit: str = ""

    def __post_init__(self) -> None:
        if not (math.isfinite(self.value) and self.low <= self.value <= self.high):
            raise InputError(self.field, f"nominal value must be in [{self.low:g}, "
                             f"{self.high:g}], got {self.value:g}")
        if not (math.isfinite(self.sd) and self.sd > 0):
            raise InputError(self.field, f"standard deviation must be > 0, got {self.sd:g}")

    def distribution(self) -> Any:
        """The frozen :func:`scipy.stats.truncnorm` of this input."""
        from scipy.stats import truncnorm

        return truncnorm((self.low - self.value) / self.sd, (self.high - self.value) / self.sd,
                         loc=self.value, scale=self.sd)

    def as_dict(self) -> dict:
        d = self.distribution()
        return {"field": self.field, "value": self.value, "sd": self.sd, "unit": self.unit,
                "distribution": "normal truncated to the valid range",
                "low": None if math.isinf(self.low) else self.low,
                "high": None if math.isinf(self.high) else self.high,
                "mean": float(d.mean()), "std": float(d.std())}


#: Truncation of each principal axis of a fit's parameters [standard deviations]: wide
#: enough that the truncation changes the variance by about 0.1 %.
FIT_TRUNCATION = 4.0


@dataclass(frozen=True)
class FitAxis(UncertainInput):
    """One principal axis of a fitted curve's parameters (:class:`ParameterFit`): a
    standard normal coordinate ``z`` (``value`` 0, ``sd`` 1), truncated to the box of
    valid curves ``[low, high]``; ``group`` is the fitted curve's field, ``axis`` the
    axis' index (largest variance first)."""

    group: str = ""
    axis: int = 0
    fit: ParameterFit | None = dataclasses.field(default=None, compare=False, repr=False)

    def as_dict(self) -> dict:
        d = super().as_dict()
        d["distribution"] = ("standard normal along a principal axis of the fit's parameter "
                             "covariance, truncated to the box of valid curves")
        d["group"], d["axis"] = self.group, self.axis
        if self.fit is not None:  # the parameters' change per unit z along this axis
            d["direction"] = dict(zip(self.fit.parameters,
                                      self.fit.axes()[1][:, self.axis].tolist(), strict=True))
        return d


@dataclass(frozen=True)
class ParameterFit:
    """The parameters of a fitted curve as an uncertain input: multivariate normal with
    the fit's ``values`` and ``covariance``, sampled along the covariance's principal axes.

    With ``covariance = V diag(lambda) V^T`` (eigen-decomposition, largest eigenvalue
    first; each eigenvector's largest component positive, for a stable sign), the
    parameters are ``p = values + V diag(sqrt(lambda)) z`` with ``z`` independent standard
    normals: one :class:`FitAxis` each, so the quasi-Monte Carlo inputs stay independent
    as Sobol' indices need. Axes of zero variance (a parameter on a bound of the fit) are
    left out.

    Truncation: ``build(p)`` returns the curve or raises
    :class:`~pdamper.errors.InputError` where ``p`` gives no valid curve (a COR outside
    (0, 1]). Each ``z_k`` is truncated to ``[-a_k, b_k]``: at most
    :data:`FIT_TRUNCATION` standard deviations, and no farther along the axis than the
    curve stays valid (bisection); the box is then shrunk by a common factor until its
    corners give valid curves. Where the valid parameters form a convex set (true of the
    exponential, linear and Thornton forms: bounds linear in the parameters) every sample
    inside the box is valid, so no sample is rejected at run time and the design stays
    balanced. The distribution sampled is thus the normal truncated to that box.
    """

    field: str
    parameters: tuple[str, ...]
    units: tuple[str, ...]
    values: np.ndarray
    covariance: np.ndarray
    build: Callable[[np.ndarray], object] = dataclasses.field(repr=False, compare=False)
    truncation: float = FIT_TRUNCATION

    def axes(self) -> tuple[np.ndarray, np.ndarray]:
        """``(sd, directions)``: the standard deviation along each principal axis (the
        square roots of the covariance's eigenvalues, largest first) and the parameters'
        change per unit ``z`` along it, ``V diag(sd)`` (columns; parameter units)."""
        cov = np.asarray(self.covariance, float)
        lam, vec = np.linalg.eigh(0.5 * (cov + cov.T))
        order = np.argsort(lam)[::-1]
        lam, vec = lam[order], vec[:, order]
        keep = lam > 1e-12 * max(float(lam[0]), 1e-300)
        lam, vec = lam[keep], vec[:, keep]
        sign = np.sign(vec[np.argmax(np.abs(vec), axis=0), np.arange(vec.shape[1])])
        vec = vec * sign
        sd = np.sqrt(lam)
        return sd, vec * sd

    def parameters_at(self, z) -> np.ndarray:
        """The parameters at principal-axis coordinates ``z`` (one per axis)."""
        return np.asarray(self.values, float) + self.axes()[1] @ np.asarray(z, float)

    def _valid(self, z) -> bool:
        try:
            self.build(self.parameters_at(z))
        except InputError:
            return False
        return True

    def limits(self) -> tuple[np.ndarray, np.ndarray]:
        """``(a, b)``: the truncation ``z_k in [-a_k, b_k]`` (class docstring)."""
        m = self.axes()[0].size
        if m == 0:
            raise InputError(self.field, "the fit's parameters have no uncertainty (zero "
                             "covariance): nothing to sample")
        if not self._valid(np.zeros(m)):
            raise InputError(self.field, "the fitted curve itself is no valid COR")
        t = self.truncation

        def reach(direction) -> float:  # how far from 0 along direction the curve is valid
            if self._valid(t * direction):
                return t
            lo, hi = 0.0, t
            for _ in range(40):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if self._valid(mid * direction) else (lo, mid)
            return lo

        eye = np.eye(m)
        a = np.array([reach(-eye[k]) for k in range(m)])
        b = np.array([reach(eye[k]) for k in range(m)])

        def box_ok(c: float) -> bool:
            return all(self._valid(c * np.where(np.array(bits, bool), b, -a))
                       for bits in np.ndindex(*(2,) * m))

        if m <= 6 and not box_ok(1.0):  # 2^m corners: a fit has a few parameters
            lo, hi = 0.0, 1.0
            for _ in range(40):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if box_ok(mid) else (lo, mid)
            a, b = a * lo, b * lo
        if not np.all(a + b > 1e-9):
            k = int(np.argmin(a + b))
            raise InputError(self.field, f"the fitted curve is on the edge of valid CORs "
                             f"along principal axis {k + 1}: its uncertainty cannot be "
                             "sampled (refit with more points, or another fit form)")
        return a, b

    def inputs(self) -> tuple[FitAxis, ...]:
        """One :class:`FitAxis` per principal axis, named ``field[pc1]``, ``field[pc2]``,
        ... (largest variance first)."""
        a, b = self.limits()
        return tuple(FitAxis(f"{self.field}[pc{k + 1}]", 0.0, 1.0, -float(a[k]),
                             float(b[k]), "1", group=self.field, axis=k, fit=self)
                     for k in range(a.size))

    def sample(self, z) -> object:
        """The curve at principal-axis coordinates ``z``."""
        return self.build(self.parameters_at(z))

    def as_dict(self) -> dict:
        sd, directions = self.axes()
        return {"field": self.field, "parameters": list(self.parameters),
                "units": list(self.units),
                "values": np.asarray(self.values, float).tolist(),
                "std": np.sqrt(np.diag(np.asarray(self.covariance, float))).tolist(),
                "covariance": np.asarray(self.covariance, float).tolist(),
                "axes_sd": sd.tolist(), "axes": directions.T.tolist(),
                "truncation": self.truncation}


def fit_groups(inputs: Sequence[UncertainInput]) -> dict[str, list[FitAxis]]:
    """The :class:`FitAxis` inputs by fitted curve (``group``), in axis order."""
    out: dict[str, list[FitAxis]] = {}
    for u in inputs:
        if isinstance(u, FitAxis):
            out.setdefault(u.group, []).append(u)
    return {g: sorted(v, key=lambda u: u.axis) for g, v in out.items()}


@dataclass(frozen=True)
class AnswerSpread:
    """The spread of one answer and what drives it."""

    name: str
    unit: str
    nominal: float
    mean: float
    std: float
    percentiles: dict[float, float]
    minimum: float
    maximum: float
    #: first-order and total Sobol' index of each input, and their bootstrap intervals
    first_order: dict[str, float] = field(default_factory=dict)
    total_order: dict[str, float] = field(default_factory=dict)
    first_order_interval: dict[str, tuple[float, float]] = field(default_factory=dict)
    total_order_interval: dict[str, tuple[float, float]] = field(default_factory=dict)
    #: per fitted curve (:func:`fit_groups`): its axes, the sum of their first-order
    #: indices (a lower bound of the curve's own first-order index) and of their total
    #: indices (an upper bound of the curve's total index): no extra run
    groups: dict[str, dict] = field(default_factory=dict)

    @property
    def ranking(self) -> list[str]:
        """The inputs, largest total index first (ties: as given)."""
        return sorted(self.total_order, key=lambda k: -self.total_order[k])

    @property
    def driver(self) -> str | None:
        """The input that drives the spread most; None without spread."""
        if not self.total_order or not any(self.total_order.values()):
            return None
        return self.ranking[0]

    def as_dict(self) -> dict:
        return {"unit": self.unit, "nominal": self.nominal, "mean": self.mean, "std": self.std,
                "percentiles": {f"p{p:g}": v for p, v in self.percentiles.items()},
                "min": self.minimum, "max": self.maximum,
                "first_order": self.first_order, "total_order": self.total_order,
                "first_order_interval": {k: list(v) for k, v in
                                         self.first_order_interval.items()},
                "total_order_interval": {k: list(v) for k, v in
                                         self.total_order_interval.items()},
                "ranking": self.ranking, "driver": self.driver,
                **({"groups": self.groups} if self.groups else {})}


@dataclass(frozen=True)
class UncertaintyResult:
    """The answers' spreads under the uncertain inputs (:func:`propagate`)."""

    inputs: tuple[UncertainInput, ...]
    answers: dict[str, AnswerSpread]
    points: int
    seed: int
    runs: int
    seconds: float
    #: the 2 n input points of A and B (d, 2 n) and the answers there (name -> (2 n,))
    samples: np.ndarray | None = field(repr=False, compare=False, default=None)
    values: dict[str, np.ndarray] = field(repr=False, compare=False, default_factory=dict)
    #: answers that are arrays (e.g. an envelope over time): name -> {"nominal", "mean",
    #: "std", "p5", ..., "p95"} per element over the 2 n points of A and B (no indices)
    bands: dict[str, dict[str, np.ndarray]] = field(repr=False, compare=False,
                                                    default_factory=dict)
    #: the inputs the sampled model does not use: field -> {"fidelity", "reason",
    #: "used_by"} (:func:`pdamper.models.registry.not_used`); their indices are 0 because
    #: the model cannot see them, not because the damper is insensitive to them
    not_used: dict[str, dict] = field(default_factory=dict)

    @property
    def driver(self) -> str | None:
        """The input driving the spread of the first answer most."""
        first = next(iter(self.answers.values()), None)
        return None if first is None else first.driver

    def as_dict(self) -> dict:
        return {"method": "quasi-Monte Carlo (scrambled Sobol', Saltelli design); "
                          "Sobol' indices: Saltelli 2010 (first order), Jansen (total)",
                "points": self.points, "seed": self.seed, "runs": self.runs,
                "seconds": self.seconds, "confidence": CONFIDENCE,
                "percentiles": list(PERCENTILES),
                "inputs": [u.as_dict() for u in self.inputs],
                "answers": {k: a.as_dict() for k, a in self.answers.items()},
                "bands": {k: {q: np.asarray(v).tolist() for q, v in b.items()}
                          for k, b in self.bands.items()},
                "driver": self.driver, "not_used": self.not_used}


def check_points(n: int, field_name: str = "uncertainty") -> int:
    """``n`` base points: a power of two in [:data:`MIN_POINTS`, :data:`MAX_POINTS`]."""
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or not (
            MIN_POINTS <= n <= MAX_POINTS) or (n & (n - 1)):
        raise InputError(field_name, f"must be a power of two in [{MIN_POINTS}, {MAX_POINTS}] "
                         f"(base points of the Sobol' design; runs = N (inputs + 2)), "
                         f"got {n!r}")
    return int(n)


def design_matrices(inputs: Sequence[UncertainInput], n: int, seed: int
                    ) -> tuple[np.ndarray, np.ndarray]:
    """The matrices A and B (each ``(d, n)``, physical values) of Saltelli's design: the
    first and last ``d`` columns of one scrambled Sobol' sequence of dimension ``2 d``."""
    from scipy.stats import qmc

    d = len(inputs)
    u = qmc.Sobol(d=2 * d, scramble=True, seed=seed).random(n).T.reshape(2, d, n)
    # the Sobol' points are in [0, 1); 0 maps to the lower end of the range: kept inside
    u = np.clip(u, 1e-12, 1.0 - 1e-12)
    for i, inp in enumerate(inputs):
        u[:, i] = inp.distribution().ppf(u[:, i])
    return u[0], u[1]


def _indices(f_a, f_b, f_ab) -> tuple[np.ndarray, np.ndarray]:
    """First-order and total indices ``(s, d)`` of the evaluations (``f_a``, ``f_b``:
    ``(s, n)``; ``f_ab``: ``(d, s, n)``) by :func:`scipy.stats.sobol_indices` (Saltelli
    2010 and Jansen); 0 where an answer has no variance."""
    import warnings

    from scipy.stats import sobol_indices

    d, s, n = f_ab.shape
    if s == 1:  # one answer and one input squeeze to a scalar in scipy: two rows kept
        f_a, f_b, f_ab = (np.concatenate([f, f], axis=-2) for f in (f_a, f_b, f_ab))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        r = sobol_indices(func={"f_A": f_a, "f_B": f_b, "f_AB": f_ab}, n=n,
                          method="saltelli_2010")
    k = max(s, 2)
    return (np.reshape(np.asarray(r.first_order, float), (k, d))[:s],
            np.reshape(np.asarray(r.total_order, float), (k, d))[:s])


def _intervals(f_a, f_b, f_ab, seed: int):
    """Percentile bootstrap intervals (:data:`CONFIDENCE`, seeded) of :func:`_indices`:
    ``((low, high) first order, (low, high) total)``, each ``(s, d)``."""
    import warnings

    from scipy.stats import bootstrap

    d, s, n = f_ab.shape

    def stat(idx):
        idx = np.asarray(idx, int)
        fo, to = _indices(f_a[:, idx], f_b[:, idx], f_ab[..., idx])
        return np.concatenate([fo.ravel(), to.ravel()])

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = bootstrap((np.arange(n),), stat, vectorized=False, n_resamples=N_RESAMPLES,
                      confidence_level=CONFIDENCE, method="percentile", rng=seed)
    lo = np.nan_to_num(np.asarray(r.confidence_interval.low, float))
    hi = np.nan_to_num(np.asarray(r.confidence_interval.high, float))
    k = s * d
    return ((lo[:k].reshape(s, d), hi[:k].reshape(s, d)),
            (lo[k:].reshape(s, d), hi[k:].reshape(s, d)))


def _group_sums(inputs, first: dict[str, float], total: dict[str, float]) -> dict:
    """Bounds of each fitted curve's own indices from those of its axes (no extra run)."""
    return {g: {"inputs": [u.field for u in axes],
                "first_order_sum": float(sum(first[u.field] for u in axes)),
                "total_order_sum": float(sum(total[u.field] for u in axes))}
            for g, axes in fit_groups(inputs).items()}


def propagate(evaluate: Callable[[dict[str, float]], dict[str, float]],
              inputs: Sequence[UncertainInput], n: int, seed: int = 0, *,
              units: dict[str, str] | None = None,
              progress: Callable[[int, int], None] | None = None,
              batch: Callable[[list[dict[str, float]]], list[dict]] | None = None
              ) -> UncertaintyResult:
    """Propagate ``inputs`` through ``evaluate`` (module docstring).

    Parameters
    ----------
    evaluate
        ``evaluate({field: value}) -> {answer: value}``: the answers at one point; the
        same answer names at every point. A float answer gets its statistics and Sobol'
        indices; an array answer (same shape at every point) its band: the mean, std and
        percentiles of each element over A and B (:attr:`UncertaintyResult.bands`).
    inputs
        The uncertain inputs (distinct fields).
    n
        Base points (:func:`check_points`); ``n (d + 2)`` evaluations in all.
    seed
        Seed of the scrambling.
    units
        Unit of each answer, for the record.
    progress
        ``progress(done, total)`` after each evaluation.
    batch
        ``batch([values, ...]) -> [answers, ...]``: every point at once (the nominal
        point first, then A, B and the AB^(i)), e.g. in parallel on the sweep engine;
        ``evaluate`` is then not called. Default: ``evaluate`` one point after another.

    Examples
    --------
    >>> r = propagate(lambda p: {"y": 2 * p["a"]}, [UncertainInput("a", 1.0, 0.1)], 256)
    >>> round(r.answers["y"].mean, 3), round(r.answers["y"].std, 2)
    (2.0, 0.2)
    """
    import time

    inputs = tuple(inputs)
    if not inputs:
        raise InputError("uncertainty", "no input carries an uncertainty: give one as "
                         "'value +- sd', e.g. friction = \"0.1 +- 0.03\"")
    names = [u.field for u in inputs]
    if len(set(names)) != len(names):
        raise InputError("uncertainty", f"each input at most once, got {names}")
    n = check_points(n)
    t0 = time.perf_counter()
    a, b = design_matrices(inputs, n, seed)
    d = len(inputs)
    if batch is not None:  # every point at once; then served from the list, in order
        mats = [a, b] + [np.where(np.arange(d)[:, None] == i, b, a) for i in range(d)]
        points = [{u.field: u.value for u in inputs}] + [
            {u.field: float(x[i, j]) for i, u in enumerate(inputs)}
            for x in mats for j in range(n)]
        answered = iter(batch(points))

        def evaluate(values):  # noqa: ARG001 - the batch's answers, in the points' order
            return next(answered)

    nominal = evaluate({u.field: u.value for u in inputs})
    answers = [k for k, v in nominal.items() if np.ndim(v) == 0]
    arrays = {k: np.asarray(v, float) for k, v in nominal.items() if np.ndim(v) > 0}
    series: dict[str, list] = {k: [] for k in arrays}
    total = n * (d + 2)
    done = 0

    def run(x: np.ndarray, keep: bool = False) -> np.ndarray:  # (d, m) -> (s, m)
        nonlocal done
        out = np.empty((len(answers), x.shape[1]))
        for j in range(x.shape[1]):
            res = evaluate({u.field: float(x[i, j]) for i, u in enumerate(inputs)})
            out[:, j] = [float(res[k]) for k in answers]
            if keep:
                for k in arrays:
                    series[k].append(np.asarray(res[k], float))
            done += 1
            if progress is not None:
                progress(done, total)
        return out

    f_a, f_b = run(a, True), run(b, True)
    f_ab = np.empty((d, len(answers), n))
    for i in range(d):
        ab = a.copy()
        ab[i] = b[i]
        f_ab[i] = run(ab)
    bad = ~np.isfinite(np.concatenate([f_a, f_b, *f_ab], axis=1))
    if bad.any():
        k = answers[int(np.argwhere(bad)[0][0])]
        raise InputError("uncertainty", f"the answer {k!r} is not finite at some samples; "
                         "narrow the inputs' standard deviations")
    out = _spreads(inputs, answers, nominal, f_a, f_b, f_ab, seed, units or {})
    both = np.concatenate([f_a, f_b], axis=1)
    bands = {k: _band(arrays[k], rows) for k, rows in series.items()}
    return UncertaintyResult(inputs, out, n, int(seed), total + 1,
                             time.perf_counter() - t0, np.concatenate([a, b], axis=1),
                             {k: both[s] for s, k in enumerate(answers)}, bands)


def _spreads(inputs: tuple[UncertainInput, ...], answers: list[str], nominal: dict,
             f_a: np.ndarray, f_b: np.ndarray, f_ab: np.ndarray, seed: int,
             units: dict[str, str]) -> dict[str, AnswerSpread]:
    """The :class:`AnswerSpread` of every float answer from the runs at A, B and the
    AB^(i) (rows: answers, columns: points)."""
    names = [u.field for u in inputs]
    first, totl = _indices(f_a, f_b, f_ab)
    ci_f, ci_t = _intervals(f_a, f_b, f_ab, seed)
    both = np.concatenate([f_a, f_b], axis=1)
    out = {}
    for s, k in enumerate(answers):
        y = both[s]
        # no spread beyond the rounding of the arithmetic: no index, no driver
        flat = float(np.ptp(y)) <= 1e-12 * max(float(np.max(np.abs(y))), 1e-300)

        def per_input(arr, s=s, flat=flat):
            return {u: 0.0 if flat else float(arr[s, i]) for i, u in enumerate(names)}

        def interval(ci, s=s, flat=flat):
            return {u: (0.0, 0.0) if flat else (float(ci[0][s, i]), float(ci[1][s, i]))
                    for i, u in enumerate(names)}

        out[k] = AnswerSpread(
            k, units.get(k, ""), float(nominal[k]), float(np.mean(y)),
            float(np.std(y, ddof=1)),
            {p: float(v) for p, v in zip(PERCENTILES, np.percentile(y, PERCENTILES),
                                         strict=True)},
            float(np.min(y)), float(np.max(y)), per_input(first), per_input(totl),
            interval(ci_f), interval(ci_t),
            _group_sums(inputs, per_input(first), per_input(totl)))
    return out


def _band(nominal: np.ndarray, rows: list) -> dict:
    """The band of an array answer over A and B: nominal, mean, std and percentiles of
    each element."""
    v = np.stack(rows)
    q = np.percentile(v, PERCENTILES, axis=0)
    return {"nominal": nominal, "mean": v.mean(axis=0), "std": v.std(axis=0, ddof=1),
            **{f"p{p:g}": q[i] for i, p in enumerate(PERCENTILES)}}


__all__ = ["FIT_TRUNCATION", "PERCENTILES", "AnswerSpread", "FitAxis", "ParameterFit",
           "UncertainInput", "UncertaintyResult", "check_points", "design_matrices",
           "fit_groups", "propagate"]
