"""Stationarity of a Level II run: is the loss factor over the averaged window steady?

The paper averages its DEM runs over cycles 3-8 (Sect. 3.1.2). For the benchmark damper that
is often a transient: at 10 Hz / 15 mm the bed dissipates eta = 2.04 over cycles 3-8 and 0.3
from cycle ~12 on. A loss factor reported as a steady value must therefore come with evidence
that its window is stationary. This module supplies that evidence from the effective loss
factor of every single cycle (Eq. 3 over one cycle; their mean over a window equals Eq. 3 over
the window, because the complex amplitudes are linear in the signal and the container
velocity is the same in every cycle).

The criterion (:class:`SteadyStateCriterion`), evaluated on the last ``L = windows x
window_cycles`` cycles after at least ``skip_cycles`` cycles:

1. **window agreement** - the mean loss factor of each of the ``windows`` consecutive windows
   of ``window_cycles`` cycles is within ``tau + z s / sqrt(window_cycles)`` of the mean over
   all ``L`` cycles, with the tolerance ``tau = max(rtol |eta|, atol)`` and ``s`` the
   cycle-to-cycle standard deviation (a granular bed is chaotic: cycle values scatter about a
   steady mean, and a window mean scatters by ``s / sqrt(m)``);
2. **no trend** - the least-squares drift of the cycle values across the ``L`` cycles is
   below ``tau``, or not significant (below ``z`` standard errors of the slope);
3. **no symmetric lattice state** - a bed that takes off while its horizontal contact forces
   on the container stay at round-off level (below ``symmetry_tolerance`` x the vertical ones
   in every cycle of the window) moves in the exact mirror symmetry of an ideal lattice in an
   ideal box. The per-cycle loss factor of that state is perfectly constant, so tests 1 and 2
   accept it, but it is a transient of the idealised initial packing: in every flying run
   of the benchmark lattice the symmetry broke after 10-30 cycles, and the loss factor then
   went to the value a random packing shows from its second cycle on (docs/fields.md).
   A resting (solid-like) bed may stay symmetric: it is steady. Nor may the window start
   within ``window_cycles`` cycles of the last symmetric cycle: the bed relaxes from the
   broken symmetry for some cycles (14 Hz / 15 mm: 0.82, 0.53, then a period-3 pattern of
   0.04-0.38 for a dozen cycles, against 0.16-0.17 after), and a window that holds the
   first of them passes tests 1 and 2 by the scatter allowance (a measured
   run: 0.263
   reported as steady over cycles 10-21).

A window of fewer than ``MIN_JUDGED_CYCLES`` (4) cycles is never steady. The tolerances
default to ``rtol = 0.1``, ``atol = 0.03`` (the resolution of the paper's
Fig. 5 colour scale, log 0.1-1), ``windows = 3`` of ``window_cycles = 4`` cycles and
``z = 2``.

**Quiet beds** are judged on a shorter window too: the same tests on ``quiet_windows`` (2)
windows of ``quiet_window_cycles`` (2) cycles after ``quiet_skip_cycles`` (1, at most
``skip_cycles``), and two more, so that the shorter window is no weaker evidence for such
a bed:

5. *quiet* - the cycle-to-cycle scatter (the larger of the standard deviation and the
   robust scale of test 1) of the bed's history, every cycle after the first or, if that
   is quieter, after the second (the paper's skip), is at most ``quiet_scatter`` (0.2) x
   ``tau``: the window means are then known to ``0.2 tau / sqrt(2)`` each, a disagreement
   or a trend cannot hide behind the scatter allowance, and a bed with a transient after
   its second cycle is left to the full window (the beds that drift slowly, scattering and
   subharmonic ones, scatter by 0.4-5 ``tau``: they are judged on the full window too).
   The history, not the four cycles of the window: four values estimate a scatter poorly,
   and a window that slides over a chaotic bed passes by chance sooner or later;
6. *no steeper trend than the full window allows* - the least-squares slope per cycle, times
   the full window's ``span - 1`` cycles, is at most ``tau`` (a 4-cycle window alone would
   let through a slope 3.7 times steeper than a 12-cycle one).

A regular bed (the solid-like and collect-and-collide harmonic beds that make most of the
paper's map) is then steady after 1 + 4 = 5 cycles instead of 14 (6 if its second cycle
still settles). Measured against the mean of cycles 21-40 of 40-cycle runs
(``benchmarks/bench_stationarity.py --windows 3x4q2w3s2,3x4,3x4q0``, docs/fields.md): see
docs/fields.md for the table; the worst points of every rule are scattering beds, which the
rule leaves to the full window.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from pdamper.analysis.complex_power import complex_amplitude
from pdamper.errors import InputError

#: Fewest cycles a window must hold to be judged steady at all (with fewer, the scatter
#: allowance of test 1 covers any difference).
MIN_JUDGED_CYCLES = 4
#: Windows of the rule for quiet beds, and the cycles it skips (module docstring):
#: chosen on 45 points of the paper's map, checked on others (docs/fields.md).
QUIET_WINDOWS = 2
QUIET_SKIP_CYCLES = 1
#: Horizontal / vertical force ratio below which a cycle counts as mirror-symmetric [-].
#: The symmetric lattice state shows <= 3e-7 (round-off); a broken symmetry >= 2e-4.
SYMMETRY_TOLERANCE = 1.0e-5


def cycle_index(time: np.ndarray, frequency: float) -> np.ndarray:
    """Number of the excitation cycle (0-based) each sample lies in; samples on a cycle
    boundary belong to the cycle they end, except the first sample."""
    c = np.ceil(np.asarray(time, float) * frequency - 1e-9).astype(int) - 1
    return np.maximum(c, 0)


def whole_cycles(time: np.ndarray, frequency: float) -> int:
    """Number of whole excitation cycles the samples ``time`` [s] span (from t = 0)."""
    t = np.asarray(time, float)
    return int(math.floor((t[-1] - t[0]) * frequency + 1e-9)) if t.size > 1 else 0


def cycle_loss_factors(time, force, velocity, frequency: float, bed_mass: float) -> np.ndarray:
    """Effective loss factor (Eq. 3) of every whole cycle ``k = 0, 1, ...`` [-].

    Parameters
    ----------
    time
        Sample times [s] from the start of the excitation, a whole number of samples per
        cycle (as :class:`pdamper.dem.DEMResult` records them).
    force
        Driving force [N] (the particle part: the container mass drops out of Eq. 3).
    velocity
        Container velocity [m/s].
    frequency
        f [Hz].
    bed_mass
        m_bed [kg].
    """
    t = np.asarray(time, float)
    n = whole_cycles(t, frequency)
    out = np.empty(n)
    period = 1.0 / frequency
    eps = 1e-9 * period
    for k in range(n):
        m = (t >= k * period - eps) & (t <= (k + 1) * period + eps)
        f_star = complex_amplitude(t[m], np.asarray(force)[m], frequency)
        v_star = complex_amplitude(t[m], np.asarray(velocity)[m], frequency)
        e_diss = 0.5 * (f_star * np.conj(v_star)).real / (2.0 * math.pi * frequency)
        out[k] = e_diss / (0.5 * bed_mass * abs(v_star) ** 2)
    return out


def cycle_symmetry(time, force, frequency: float) -> np.ndarray:
    """Largest horizontal over largest vertical force of every whole cycle [-].

    ``force`` has shape (n, 3); a bed in the mirror symmetry of an ideal lattice gives
    round-off (~1e-8), any asymmetry ~0.1-1.
    """
    t = np.asarray(time, float)
    f = np.asarray(force, float)
    n = whole_cycles(t, frequency)
    c = cycle_index(t, frequency)
    out = np.empty(n)
    for k in range(n):
        m = c == k
        vert = float(np.max(np.abs(f[m, 2]))) if m.any() else 0.0
        horiz = float(np.max(np.abs(f[m, :2]))) if m.any() else 0.0
        out[k] = horiz / vert if vert > 0 else (math.inf if horiz > 0 else 0.0)
    return out


@dataclass(frozen=True)
class Stationarity:
    """Verdict of :class:`SteadyStateCriterion` on a series of cycle loss factors.

    Attributes
    ----------
    stationary
        All three tests pass.
    reason
        Empty when stationary, else what failed (``"too few cycles"``, ``"windows
        disagree"``, ``"trend"``, ``"symmetric lattice state"``, ``"relaxing from a
        symmetric lattice state"``).
    cycles
        Whole cycles evaluated [-].
    first_cycle, last_cycle
        The averaged window, 1-based and inclusive (the paper's "cycles 3-8") [-].
    loss_factor
        Mean loss factor over the window [-].
    stderr
        Its standard error ``s / sqrt(L)`` [-].
    spread
        Largest deviation of a window mean from the mean [-].
    drift
        Least-squares change of the cycle loss factor across the window [-].
    tolerance
        ``tau = max(rtol |eta|, atol)`` [-].
    symmetric
        The bed kept the mirror symmetry of an ideal lattice in every cycle of the window.
    quiet
        The window was judged by the rule for quiet beds (windows of
        ``quiet_window_cycles`` cycles), not the full one.
    """

    stationary: bool
    reason: str
    cycles: int
    first_cycle: int
    last_cycle: int
    loss_factor: float
    stderr: float
    spread: float
    drift: float
    tolerance: float
    symmetric: bool
    quiet: bool = False

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class SteadyStateCriterion:
    """When a Level II run has reached its steady state (module docstring).

    Parameters
    ----------
    window_cycles
        Cycles per window m [-].
    windows
        Number of consecutive windows k compared [-]; the averaged window has k m cycles.
    rtol, atol
        Relative and absolute tolerance on the loss factor [-].
    z
        Allowance for the cycle-to-cycle scatter, in standard errors [-].
    skip_cycles
        Cycles never averaged (the start-up from rest) [-].
    symmetry_tolerance
        See :data:`SYMMETRY_TOLERANCE` [-].
    quiet_window_cycles
        Cycles per window of the rule for quiet beds [-] (0: none; see the module
        docstring).
    quiet_scatter
        Largest cycle-to-cycle scatter of a quiet bed, relative to the tolerance [-].
    quiet_windows
        Number of windows the rule for quiet beds compares [-].
    quiet_skip_cycles
        Cycles never averaged in a quiet bed's window [-]; at most ``skip_cycles``
        (:attr:`quiet_skip`).

    Examples
    --------
    A bed at 0.3 from its second cycle on is quiet: steady after five cycles, averaged over
    cycles 2-5. One that settles from 2.0 to 0.3 only after six cycles, or scatters from
    cycle to cycle by 5 %, needs the full window, the last 12 cycles:

    >>> c = SteadyStateCriterion()
    >>> quiet = [2.0] + [0.3] * 5
    >>> c.evaluate(quiet[:4]).stationary, c.evaluate(quiet[:5]).stationary
    (False, True)
    >>> c.evaluate(quiet[:5]).first_cycle, c.evaluate(quiet[:5]).quiet
    (2, True)
    >>> late = [2.0] * 6 + [0.3] * 12
    >>> c.evaluate(late[:17]).stationary, c.evaluate(late).stationary
    (False, True)
    >>> noisy = [2.0] * 6 + [0.3 * (1 + 0.05 * (-1) ** k) for k in range(12)]
    >>> c.evaluate(noisy[:17]).stationary, c.evaluate(noisy).stationary
    (False, True)
    >>> c.evaluate(noisy[:17]).reason
    'windows disagree'
    """

    window_cycles: int = 4
    windows: int = 3
    rtol: float = 0.1
    atol: float = 0.03
    z: float = 2.0
    skip_cycles: int = 2
    symmetry_tolerance: float = SYMMETRY_TOLERANCE
    quiet_window_cycles: int = 2
    quiet_scatter: float = 0.2
    quiet_windows: int = QUIET_WINDOWS
    quiet_skip_cycles: int = QUIET_SKIP_CYCLES

    def __post_init__(self) -> None:
        for name, low in (("window_cycles", 1), ("windows", 2), ("skip_cycles", 0),
                          ("quiet_window_cycles", 0), ("quiet_windows", 2),
                          ("quiet_skip_cycles", 0)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < low:
                raise InputError(f"dem.{name}", f"must be a whole number >= {low}, got {v!r}")
        for name in ("rtol", "atol", "z", "symmetry_tolerance", "quiet_scatter"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and math.isfinite(v) and v >= 0):
                raise InputError(f"dem.steady_{name}" if name in ("rtol", "atol") else
                                 f"dem.{name}", f"must be a finite number >= 0, got {v!r}")

    @property
    def span(self) -> int:
        """Cycles in the averaged window, ``windows x window_cycles``."""
        return self.windows * self.window_cycles

    @property
    def quiet_span(self) -> int:
        """Cycles in the averaged window of a quiet bed, ``quiet_windows x
        quiet_window_cycles`` (0: no quiet rule: ``quiet_window_cycles`` or
        ``quiet_scatter`` 0, a window no shorter than the full one, or fewer than
        ``MIN_JUDGED_CYCLES`` cycles)."""
        q = self.quiet_windows * self.quiet_window_cycles
        quiet = (self.quiet_scatter > 0 and MIN_JUDGED_CYCLES <= q < self.span
                 and self.quiet_window_cycles > 0)
        return q if quiet else 0

    @property
    def quiet_skip(self) -> int:
        """Cycles skipped before a quiet bed's window, ``min(quiet_skip_cycles,
        skip_cycles)``: a quiet bed shows in its own window that its start-up is over."""
        return min(self.quiet_skip_cycles, self.skip_cycles)

    @property
    def min_cycles(self) -> int:
        """Fewest cycles a run needs before it can be steady (a quiet bed's)."""
        if self.quiet_span:
            return min(self.quiet_skip + self.quiet_span, self.full_cycles)
        return self.full_cycles

    @property
    def full_cycles(self) -> int:
        """Cycles a run needs before any bed can be judged steady (the full window)."""
        return self.skip_cycles + self.span

    def evaluate(self, loss_factors, symmetry=None, resting: bool = False) -> Stationarity:
        """Judge the last :attr:`span` cycles of ``loss_factors`` (one value per cycle).

        Parameters
        ----------
        loss_factors
            Effective loss factor of each whole cycle, in order [-].
        symmetry
            :func:`cycle_symmetry` of each cycle (None: not tested).
        resting
            The bed does not take off (solid-like): a symmetric state is then steady.
        """
        eta = np.asarray(loss_factors, float)
        full = self._judge(eta, self.span, self.window_cycles, symmetry, resting)
        if full.stationary or not self.quiet_span:
            return full
        quiet = self._judge(eta, self.quiet_span, self.quiet_window_cycles, symmetry, resting,
                            quiet=True)
        return quiet if quiet.stationary else full

    def _judge(self, eta: np.ndarray, span: int, m: int, symmetry, resting: bool,
               quiet: bool = False) -> Stationarity:
        """Tests 1-4 on the last ``span`` cycles in windows of ``m``; with ``quiet`` also
        tests 5 and 6 (module docstring), after :attr:`quiet_skip` cycles."""
        n = eta.size
        L = min(span, max(n - (self.quiet_skip if quiet else self.skip_cycles), 0))
        first = n - L + 1
        if L < 2:
            mean = float(eta[-1]) if n else math.nan
            return Stationarity(False, "too few cycles", n, max(first, 1), n, mean, math.nan,
                                math.nan, math.nan, math.nan, False)
        win = eta[n - L:]
        mean = float(win.mean())
        s = float(win.std(ddof=1))
        # the scatter allowance from the median absolute deviation: one transient cycle in
        # the window must not widen the allowance that is meant to detect it
        robust = 1.4826 * float(np.median(np.abs(win - np.median(win))))
        tau = max(self.rtol * abs(mean), self.atol)
        blocks = [win[i:i + m] for i in range(L % m, L, m)] if L >= m else [win]
        spread = max(abs(float(b.mean()) - mean) for b in blocks)
        c = np.arange(L, dtype=float)
        c -= c.mean()
        sxx = float(c @ c)
        slope = float(c @ (win - mean)) / sxx
        resid = win - mean - slope * c
        se_slope = math.sqrt(float(resid @ resid) / max(L - 2, 1) / sxx) if L > 2 else math.inf
        drift = abs(slope) * (L - 1)
        symmetric = bool(symmetry is not None and len(symmetry) >= n
                         and np.any(np.asarray(symmetry, float)[n - L:n]
                                    < self.symmetry_tolerance))
        # cycles between the last symmetric cycle and the window (none: n)
        after = n
        if symmetry is not None and len(symmetry) >= n:
            sym = np.nonzero(np.asarray(symmetry, float)[:n] < self.symmetry_tolerance)[0]
            if sym.size:
                after = (n - L) - (int(sym[-1]) + 1)
        reason = ""
        if L < span or L < MIN_JUDGED_CYCLES:
            reason = "too few cycles"
        elif spread > tau + self.z * robust / math.sqrt(m):
            reason = "windows disagree"
        elif drift > tau and abs(slope) > self.z * se_slope:
            reason = "trend"
        elif symmetric and not resting:
            reason = "symmetric lattice state"
        elif after < self.window_cycles and not resting:
            reason = "relaxing from a symmetric lattice state"
        elif quiet and self._history_scatter(eta) > self.quiet_scatter * tau:
            reason = "not quiet"
        elif quiet and abs(slope) * (self.span - 1) > tau:
            reason = "trend"
        return Stationarity(not reason, reason, n, first, n, mean, s / math.sqrt(L), spread,
                            drift, tau, symmetric, quiet)

    def _history_scatter(self, eta: np.ndarray) -> float:
        """Scatter of test 5: the larger of the standard deviation and the robust scale of
        every cycle after :attr:`quiet_skip` or, if that is smaller and holds the window,
        after ``skip_cycles``; not of the window alone (four values estimate a scatter too
        poorly: judged on its window, a bed scattering by 0.5 tau passed as quiet in 28 %
        of 400 synthetic runs, judged on its history in 9 %, the 6-cycle window of three
        windows of two cycles after two in 6 %; docs/fields.md)."""
        best = math.inf
        for start in {self.quiet_skip, self.skip_cycles}:
            h = eta[start:]
            if h.size >= max(self.quiet_span, 2):
                robust = 1.4826 * float(np.median(np.abs(h - np.median(h))))
                best = min(best, max(float(h.std(ddof=1)), robust))
        return best
