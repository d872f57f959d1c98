"""Analytical model of a vertically driven particle bed (paper Sect. 3.1, Eqs. 5-22).

The bed is one inelastic block (collect-and-collide): it takes off the container bottom when
the container decelerates faster than gravity (Eq. 5), flies on a parabola and adopts the
wall's velocity at every impact. Which wall it hits first, and when, decides the motion mode
(Fig. 4); the relative impact velocities give the dissipated energy per cycle (Eqs. 8, 10,
15), the effective loss factor (Eq. 3 with Eqs. 8/10/15) and, via Eq. (22), the effective
particle mass.

Everything is computed in the dimensionless phase ``phi = W t`` and positions in units of
the stroke ``X``: the container is ``y_c = sin(phi)``, the bed's flight from take-off phase
``phi_0`` is ``y_b = sin(phi_0) + cos(phi_0) s - s^2 / (2 Gamma)``, ``s = phi - phi_0``, with
``Gamma = A / g`` the dimensionless acceleration and velocities in units of ``V = X W``.
All functions are vectorised over broadcastable arrays of (frequency, stroke, clearance).

Conventions fixed where the printed paper is ambiguous:

- A vibration cycle runs from ``phi = pi/2`` to ``5 pi/2``; take-off (Eq. 5) lies in
  ``(0, pi/2)``.
- Eq. (12): ``n_s = floor((phi_imp - pi/2) / 2 pi)`` whole cycles of delay,
  ``kappa = 1 / (1 + n_s)``.
- Eq. (18) as printed is empty for ``n_s = 0``; we use the reading its next sentence gives:
  a bottom impact in cycle ``n = floor((phi - pi/2) / 2 pi)`` has ``n_s = n``, except that a
  harmonic one (``n = 0``) after the next take-off, ``phi in (phi_0 + 2 pi, 5 pi/2)``, is
  scattering. One could extend that scattering band to every ``n``; that would make the
  paper's own example of a subharmonic bottom impact (Fig. 4-3ii, X = 20 mm, f = 18 Hz,
  impact at ``phi = 12.80`` against ``phi_0 + 4 pi = 12.60``) scattering. Physically the bed
  then re-launches at once with almost the regular take-off velocity (the container still
  decelerates at ~6 g), which is the paper's "conditionally repetitive" trajectory, so for
  ``n_s >= 1`` the whole cycle is subharmonic.
- A top impact after the next take-off time (``phi_st > phi_0 + 2 pi``, a subharmonic top
  impact, Fig. 4-3iii) is scattering (Eq. 8), as is a second top impact before the bed
  has returned to the bottom.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from pdamper.analysis.modes import EFFECTIVE_MASS_RATIO, MotionMode
from pdamper.constants import STANDARD_GRAVITY
from pdamper.errors import InputError, SimulationError, check_range

#: Eq. (8): solid-like and scattering beds dissipate 1/1000 of 2 pi E_kin per cycle.
SOLID_LOSS_FACTOR = 1.0e-3

#: Zero-gravity optimum of the double collect-and-collide mode, Eq. (21).
ETA_MAX = 4.0 / math.pi

_SAMPLES_PER_CYCLE = 256
#: :data:`EFFECTIVE_MASS_RATIO` indexed by the modes' integer codes.
_RATIO_BY_CODE = np.full(max(int(m) for m in MotionMode) + 1, np.nan)
for _mode, _ratio in EFFECTIVE_MASS_RATIO.items():
    _RATIO_BY_CODE[int(_mode)] = _ratio
_BISECTIONS = 60
#: Phase tolerance [rad] of comparisons of two impact phases found by bisection.
_PHASE_TOL = 1e-9
#: Longest flight [excitation cycles] the phase scan follows. Inputs a damper can have stay
#: far below (the physics checks of pdamper.resources bound the acceleration ratio to
#: ~1e6, a flight to ~3e5 cycles); beyond, the answer is an error, not minutes of scanning.
MAX_FLIGHT_CYCLES = 1_000_000
#: Flight from the lid [cycles] beyond which the bed counts as scattering: a subharmonic of
#: order k dissipates eta <= ETA_MAX / (1 + k) (Eq. 18, dv_st, dv_nd <= 2 V), below the
#: scattering bed's SOLID_LOSS_FACTOR (Eq. 8) from k = ETA_MAX / SOLID_LOSS_FACTOR on.
_DRIFT_CYCLES = 1274


def optimal_stroke(clearance):
    """Optimal container stroke ``X_opt = h / pi`` [m] (Eq. 19).

    >>> round(optimal_stroke(0.1) * 1000, 1)
    31.8
    """
    return np.asarray(clearance, float) / math.pi if np.ndim(clearance) else clearance / math.pi


def clearance_from_count(n_particles, n_max: int, length: float):
    """Clearance ``h = L (1 - n_p / n_max)`` [m] between bed and lid (paper Sect. 3.1.1).

    >>> clearance_from_count(32, 192, 0.12)
    0.1
    """
    n = np.asarray(n_particles, float)
    if np.any(n < 0) or np.any(n > n_max):
        raise InputError("particles.count", f"must be in [0, {n_max}], got {n_particles}")
    h = length * (1.0 - n / n_max)
    return float(h) if np.ndim(h) == 0 else h


@dataclass(frozen=True)
class BedResponse:
    """Analytical response of the particle bed at each (frequency, stroke) point.

    All arrays share the broadcast shape of the inputs. Phases are ``W t`` [rad]; NaN where
    the event does not occur in that mode.

    Attributes
    ----------
    mode
        :class:`MotionMode` integer codes.
    subharmonic_order
        ``n_s`` of Eqs. (12)/(18) [-] (0 for harmonic modes, -1 where undefined).
    takeoff_phase
        Take-off from the bottom, Eq. (5).
    top_impact_phase, top_release_phase
        First impact with the lid (Eq. 7) and release from it (Eq. 13).
    bottom_impact_phase
        Impact with the bottom (Eq. 9 for single, Eq. 14 for double CaC).
    relative_velocity_top, relative_velocity_bottom
        Delta v_st / Delta v_nd of Eqs. (11), (16), (17) [m/s].
    dissipated_energy_per_cycle
        E~_diss [J], Eqs. (8), (10), (15).
    loss_factor
        Effective loss factor eta [-], Eq. (3).
    effective_mass_ratio
        Effective particle mass over bed mass [-], Eq. (22).
    """

    frequency: np.ndarray
    amplitude: np.ndarray
    clearance: np.ndarray
    bed_mass: np.ndarray
    mode: np.ndarray
    subharmonic_order: np.ndarray
    takeoff_phase: np.ndarray
    top_impact_phase: np.ndarray
    top_release_phase: np.ndarray
    bottom_impact_phase: np.ndarray
    relative_velocity_top: np.ndarray
    relative_velocity_bottom: np.ndarray
    dissipated_energy_per_cycle: np.ndarray
    loss_factor: np.ndarray
    effective_mass_ratio: np.ndarray
    gravity: float = field(default=STANDARD_GRAVITY)

    @property
    def effective_mass(self) -> np.ndarray:
        """Effective particle mass [kg], Eq. (22)."""
        return self.effective_mass_ratio * self.bed_mass

    @property
    def optimal_stroke(self) -> np.ndarray:
        """X_opt = h / pi [m], Eq. (19)."""
        return self.clearance / math.pi

    def modes(self) -> np.ndarray:
        """The modes as an object array of :class:`MotionMode`."""
        return np.vectorize(MotionMode, otypes=[object])(self.mode)


def _floats(name: str, value, unit: str) -> np.ndarray:
    if isinstance(value, str | bytes):
        raise InputError(name, f"must be a number or an array of numbers in {unit}, got "
                         f"{value!r}")
    try:
        return np.asarray(value, float)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a number or an array of numbers in {unit}, got "
                         f"{value!r}") from None


def _out_of_range(i: int, frequency, amplitude, gam, why: str) -> InputError:
    f, x = float(frequency[i]), float(amplitude[i])
    return InputError("amplitude" if x > 1.0 else "frequency",
                      f"at f = {f:.3g} Hz, X = {x:.3g} m {why} (acceleration ratio "
                      f"X (2 pi f)^2 / g = {float(gam[i]):.3g}): outside the analytical "
                      f"model's range; lower the amplitude or the frequency")


def _check_flight(phi_start, max_phase, active, frequency, amplitude, gam) -> None:
    """Refuse flights longer than :data:`MAX_FLIGHT_CYCLES` (the scan's bound)."""
    with np.errstate(invalid="ignore"):
        span = np.where(active, max_phase - phi_start, 0.0)
    bad = ~(span <= 2.0 * math.pi * MAX_FLIGHT_CYCLES)  # NaN and inf included
    if np.any(bad):
        raise _out_of_range(int(np.flatnonzero(bad)[0]), frequency, amplitude, gam,
                            f"the bed would fly for more than {MAX_FLIGHT_CYCLES:.0e} cycles")


def _validate(name: str, arr: np.ndarray, low: float, unit: str, strict: bool = True) -> None:
    if not np.all(np.isfinite(arr)):
        raise InputError(name, f"must be finite, got {arr[~np.isfinite(arr)].ravel()[0]}")
    bad = arr <= low if strict else arr < low
    if np.any(bad):
        op = ">" if strict else ">="
        raise InputError(name, f"must be {op} {low:g} {unit}, got {arr[bad].ravel()[0]:g} {unit}")


def _flight_span(y0, c, low, high, gam):
    """Phase span [rad] after which a free flight ``y0 + c s - s^2 / (2 Gamma)`` (positions
    in strokes) has left the band ``[low, high]`` the container's walls sweep: the first of
    its fall below ``low`` and its rise above ``high`` (inf where it does neither; a bed at
    rest in the container's mean frame without gravity). The roots are written without
    cancellation, so that ``Gamma -> inf`` (weak gravity) tends to the straight flight of
    ``Gamma = inf`` (none)."""
    d, e = y0 - low, high - y0
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        root = np.sqrt(c**2 + 2.0 * d / gam)
        fall = np.where(c < 0, 2.0 * d / (root - c), gam * (c + root))
        disc = c**2 - 2.0 * e / gam
        rise = np.where((c > 0) & (disc >= 0), 2.0 * e / (c + np.sqrt(np.maximum(disc, 0.0))),
                        np.inf)
    return np.fmin(np.where(np.isnan(fall), np.inf, fall), rise)


@dataclass(frozen=True)
class _Gap:
    """The gap ``y(phi) - sin(phi) - offset`` [strokes] between a flying bed and a wall of
    the container, with the bed's flight the parabola ``y = base + slope s - s^2 / gam2``,
    ``s = phi - p0`` (Eqs. 7, 9, 14; ``gam2 = 2 Gamma``, inf without gravity): one array
    per parameter over all points, rows picked by index. The arithmetic is written once
    (:meth:`values`), in the same order for an array of phases and for one phase, so that
    one point alone and one point of many give the same bits."""

    p0: np.ndarray
    base: np.ndarray
    slope: np.ndarray
    gam2: np.ndarray
    offset: np.ndarray

    def rows(self, idx: np.ndarray) -> tuple:
        """The parameters of the rows ``idx`` as columns (to broadcast over a phase grid)."""
        return tuple(a[idx, None] for a in (self.p0, self.base, self.slope, self.gam2,
                                            self.offset))

    @staticmethod
    def values(phi, p0, base, slope, gam2, offset):
        s = phi - p0
        return base + slope * s - (s * s) / gam2 - np.sin(phi) - offset

    def bounds(self, row: int, lo: float, hi: float) -> tuple[float, float]:
        """Lower and upper bounds of the gap of point ``row`` over phases [lo, hi]: the
        parabola's extremes there (its ends, and its top where the parabola opens
        downwards), minus ``offset``, then -1 and +1 for the sine. Widened by a margin
        of 1e-9 of the largest term, some million times the round-off of the gap's
        arithmetic: a cycle these bounds exclude holds no crossing on the grid either."""
        p0, base, slope, gam2 = (float(self.p0[row]), float(self.base[row]),
                                 float(self.slope[row]), float(self.gam2[row]))
        off = float(self.offset[row])

        def y(phi: float) -> float:
            s = phi - p0
            return base + slope * s - (s * s) / gam2

        ends = (y(lo), y(hi))
        low, high = min(ends), max(ends)
        vertex = p0 + 0.5 * slope * gam2 if math.isfinite(gam2) else math.nan
        if lo < vertex < hi:
            high = max(high, y(vertex))
        s = max(abs(lo - p0), abs(hi - p0))
        margin = 1e-9 * (1.0 + abs(base) + abs(slope) * s + s * s / gam2 + abs(off)
                         + abs(low) + abs(high))
        return low - off - 1.0 - margin, high - off + 1.0 + margin

    def bounds_rows(self, idx: np.ndarray, lo: np.ndarray, hi: np.ndarray):
        """:meth:`bounds` of the rows ``idx``, each over its [lo, hi] (arrays). The same
        arithmetic as :meth:`bounds`, written twice on purpose: one point's scan asks for
        a bound per cycle (up to a million cycles without gravity), where numpy's calls on
        scalars would cost several times the Python floats of :meth:`bounds`."""
        p0, base, slope, gam2, off = (a[idx] for a in (self.p0, self.base, self.slope,
                                                        self.gam2, self.offset))
        with np.errstate(invalid="ignore"):
            def y(phi):
                s = phi - p0
                return base + slope * s - (s * s) / gam2

            y_lo, y_hi = y(lo), y(hi)
            low, high = np.minimum(y_lo, y_hi), np.maximum(y_lo, y_hi)
            vertex = np.where(np.isfinite(gam2), p0 + 0.5 * slope * gam2, np.nan)
            inside = (lo < vertex) & (vertex < hi)
            high = np.where(inside, np.maximum(high, y(np.where(inside, vertex, lo))), high)
            s = np.maximum(np.abs(lo - p0), np.abs(hi - p0))
            margin = 1e-9 * (1.0 + np.abs(base) + np.abs(slope) * s + s * s / gam2
                             + np.abs(off) + np.abs(low) + np.abs(high))
        return low - off - 1.0 - margin, high - off + 1.0 + margin


def _first_crossing(gap: _Gap, phi_start, active, max_phase, rising: bool):
    """First phase > phi_start where ``gap`` crosses zero.

    ``rising``: crossing from negative to >= 0 (else from positive to <= 0). Scans cycle by
    cycle on a fine phase grid and refines the bracketing interval by bisection. Returns NaN
    where no crossing occurs before ``max_phase``. The scan ends after at most
    ``(max_phase - phi_start) / 2 pi + 2`` cycles, which the caller bounds
    (:func:`_check_flight`).

    One point alone (the harmonic balance's root search asks for one at a time) is scanned
    by :func:`_first_crossing_one`: the same grid, the same arithmetic, the same bits, at a
    fraction of the cost of numpy's calls on arrays of one row.
    """
    n = phi_start.size
    result = np.full(n, np.nan)
    todo = np.flatnonzero(active & np.isfinite(phi_start))
    if todo.size == 0:
        return result
    k = _SAMPLES_PER_CYCLE
    # the gap is zero at phi_start itself for take-off; start just after it
    offsets = np.arange(1, k + 1) * (2.0 * math.pi / k)
    lo_phase = phi_start[todo].copy()
    span = float(np.max(max_phase[todo] - lo_phase))
    if not span <= 2.0 * math.pi * MAX_FLIGHT_CYCLES:
        raise SimulationError(f"phase scan over {span:.3g} rad: the flight was not bounded")
    cycles = int(math.ceil(span / (2.0 * math.pi))) + 2
    if todo.size == 1:
        i = int(todo[0])
        result[i] = _first_crossing_one(gap, i, float(lo_phase[0]), float(max_phase[i]),
                                        rising, offsets, cycles)
        return result
    for cycle in range(cycles):
        if not todo.size:
            break
        shift = (2.0 * math.pi / k) * (cycle == 0) * 0.999
        end = lo_phase + offsets[-1] - shift  # the grid's last phase, as the grid has it
        # the grid is evaluated only where the gap's bounds allow a crossing this cycle
        low, high = gap.bounds_rows(todo, lo_phase, end)
        scan = np.flatnonzero(high >= 0 if rising else low <= 0)
        any_hit = np.zeros(todo.size, bool)
        if scan.size:
            grid = lo_phase[scan, None] + offsets[None, :] - shift
            vals = gap.values(grid, *gap.rows(todo[scan]))
            hit = vals >= 0 if rising else vals <= 0
            any_hit[scan] = hit.any(axis=1)
            rows = np.flatnonzero(any_hit[scan])
            if rows.size:
                j = hit[rows].argmax(axis=1)
                b = grid[rows, j]
                a = np.where(j > 0, grid[rows, np.maximum(j - 1, 0)], lo_phase[scan[rows]])
                params = gap.rows(todo[scan[rows]])
                for _ in range(_BISECTIONS):
                    m = 0.5 * (a + b)
                    gm = gap.values(m[:, None], *params)[:, 0]
                    h = gm >= 0 if rising else gm <= 0
                    b2, a2 = np.where(h, m, b), np.where(h, a, m)
                    if np.array_equal(a2, a) and np.array_equal(b2, b):
                        break  # a fixed point: the bisections left would not move it
                    a, b = a2, b2
                result[todo[scan[rows]]] = b
        keep = ~any_hit & (end < max_phase[todo])
        todo = todo[keep]
        lo_phase = end[keep]
    if todo.size:  # the bound above is exact: never here
        raise SimulationError(f"phase scan did not end within {cycles} cycles")
    return result


def _first_crossing_one(gap: _Gap, i: int, lo: float, max_phase: float, rising: bool,
                        offsets: np.ndarray, cycles: int) -> float:
    """:func:`_first_crossing` of the one point ``i`` from phase ``lo``: the same grid and
    arithmetic, the bisection on Python floats, and cycles that the gap's bounds
    (:meth:`_Gap.bounds`) show to hold no crossing passed over without evaluating the grid
    (a long flight without gravity spans up to a million cycles). The phases stepped over
    are the grid's, added cycle by cycle as the scan adds them."""
    params = tuple(float(a[i]) for a in (gap.p0, gap.base, gap.slope, gap.gam2, gap.offset))
    first = (2.0 * math.pi / offsets.size) * 0.999
    last = float(offsets[-1])
    for cycle in range(cycles):
        end = lo + last - (first if cycle == 0 else 0.0)
        low, high = gap.bounds(i, lo, end)
        if (high < 0.0) if rising else (low > 0.0):  # no crossing in this cycle
            if not end < max_phase:
                return math.nan
            lo = end
            continue
        grid = lo + offsets - (first if cycle == 0 else 0.0)
        vals = _Gap.values(grid, *params)
        hit = vals >= 0 if rising else vals <= 0
        if hit.any():
            j = int(hit.argmax())
            b = float(grid[j])
            a = float(grid[j - 1]) if j > 0 else lo
            for _ in range(_BISECTIONS):
                m = 0.5 * (a + b)
                gm = float(_Gap.values(m, *params))
                if (gm >= 0) if rising else (gm <= 0):
                    if m == b:
                        break  # a fixed point, as in the scan of many points
                    b = m
                else:
                    if m == a:
                        break
                    a = m
            return b
        if not float(grid[-1]) < max_phase:
            return math.nan
        lo = float(grid[-1])
    raise SimulationError(f"phase scan did not end within {cycles} cycles")


def bed_response(
    frequency,
    amplitude,
    clearance,
    bed_mass,
    gravity: float = STANDARD_GRAVITY,
) -> BedResponse:
    """Motion mode, impacts, dissipation and effective mass of the bed (Eqs. 5-22).

    Parameters
    ----------
    frequency : array_like
        Excitation frequency f [Hz], > 0.
    amplitude : array_like
        Container stroke amplitude X [m], > 0 (``x_c = X sin(2 pi f t)``).
    clearance : array_like
        Clearance h between bed and lid [m], >= 0.
    bed_mass : array_like
        Mass of all particles m_bed [kg], >= 0.
    gravity
        g [m/s^2].

    Returns
    -------
    BedResponse
        Arrays of the broadcast shape of the inputs.

    Examples
    --------
    The paper's double collect-and-collide example (Fig. 4-3i):

    >>> r = bed_response(18.0, 0.050, 0.1, 0.132)
    >>> MotionMode(int(r.mode)).label
    'double_cac_harmonic'
    """
    f, x, h, m, gravity, shape = _bed_inputs(frequency, amplitude, clearance, bed_mass, gravity)
    b = _Flights.start(f, x, h, gravity)
    top = _first_crossing(b.gap(b.ht), b.phi0, b.flying, b.max_phase, rising=True)
    # a bottom impact counts only before the lid's: no need to scan the flight beyond it
    bot = _first_crossing(b.gap(np.zeros_like(b.ht)), b.phi0, b.flying,
                          np.fmin(b.max_phase, top), rising=False)
    double = b.flying & np.isfinite(top) & ~(np.isfinite(bot) & (bot < top))
    b.single_cac(np.flatnonzero(b.flying & ~double), bot)
    b.double_cac(np.flatnonzero(double), top)

    scattering = b.mode == int(MotionMode.SCATTERING)
    b.eta[scattering] = SOLID_LOSS_FACTOR  # Eq. (8)
    b.ns[scattering] = -1
    v = x * b.w
    with np.errstate(over="ignore"):
        e_tilde = b.eta * math.pi * m * v**2  # E~ = 2 pi * eta * (1/2 m V^2)
    if not np.all(np.isfinite(e_tilde)):
        raise _out_of_range(int(np.flatnonzero(~np.isfinite(e_tilde))[0]), f, x, b.gam,
                            "the container's kinetic energy overflows")
    ratio = _RATIO_BY_CODE[b.mode]  # the table of Eq. (22) by mode code
    b.phi_tt[~double] = np.nan

    def out(a):
        return a.reshape(shape)

    return BedResponse(
        frequency=out(f), amplitude=out(x), clearance=out(h), bed_mass=out(m),
        mode=out(b.mode), subharmonic_order=out(b.ns), takeoff_phase=out(b.phi0),
        top_impact_phase=out(b.phi_st), top_release_phase=out(b.phi_tt),
        bottom_impact_phase=out(b.phi_nd), relative_velocity_top=out(b.dv_st * v),
        relative_velocity_bottom=out(b.dv_nd * v), dissipated_energy_per_cycle=out(e_tilde),
        loss_factor=out(b.eta), effective_mass_ratio=out(ratio), gravity=gravity,
    )


def _bed_inputs(frequency, amplitude, clearance, bed_mass, gravity: float):
    """The inputs of :func:`bed_response` checked, broadcast and flattened, with the
    broadcast shape."""
    f, x, h, m = np.broadcast_arrays(*(_floats(name, v, unit) for name, v, unit in (
        ("frequency", frequency, "Hz"), ("amplitude", amplitude, "m"),
        ("clearance", clearance, "m"), ("bed_mass", bed_mass, "kg"))))
    _validate("frequency", f, 0.0, "Hz")
    _validate("amplitude", x, 0.0, "m")
    _validate("clearance", h, 0.0, "m", strict=False)
    _validate("bed_mass", m, 0.0, "kg", strict=False)
    gravity = check_range("gravity", gravity, low=0.0, unit="m/s^2")
    shape = f.shape
    f, x, h, m = (a.ravel() for a in (f, x, h, m))
    return f, x, h, m, gravity, shape


@dataclass
class _Flights:
    """The flights of the bed over one cycle at every point (flat arrays, phases in rad,
    velocity changes in units of V = X omega), filled in by the motion modes in turn."""

    f: np.ndarray
    x: np.ndarray
    gam: np.ndarray  # Gamma = A / g
    ht: np.ndarray  # clearance in strokes h / X
    w: np.ndarray  # omega [rad/s]
    flying: np.ndarray
    phi0: np.ndarray  # take-off phase, Eq. (5)
    s0: np.ndarray  # sin(phi0)
    c0: np.ndarray  # cos(phi0)
    max_phase: np.ndarray  # the last phase a first flight may reach a wall
    mode: np.ndarray
    ns: np.ndarray
    phi_st: np.ndarray
    phi_tt: np.ndarray
    phi_nd: np.ndarray
    dv_st: np.ndarray
    dv_nd: np.ndarray
    eta: np.ndarray

    @classmethod
    def start(cls, f: np.ndarray, x: np.ndarray, h: np.ndarray, gravity: float) -> _Flights:
        with np.errstate(over="ignore"):
            w = 2.0 * math.pi * f
            # Gamma = A / g; without gravity Gamma = inf: take-off at phi_0 = 0 (Eq. 5),
            # straight flights (Eqs. 7, 9, 14) and release from the lid at phi = pi (Eq. 13)
            gam = x * w**2 / gravity if gravity > 0 else np.full_like(x, math.inf)
        if gravity > 0 and not np.all(np.isfinite(gam)):
            raise _out_of_range(int(np.flatnonzero(~np.isfinite(gam))[0]), f, x, gam,
                                "the container acceleration overflows")
        with np.errstate(over="ignore"):  # a vanishing stroke: the lid is out of reach
            ht = h / x  # clearance in strokes
        n = f.size
        nan = np.full(n, np.nan)
        phi0 = nan.copy()
        flying = gam > 1.0
        phi0[flying] = np.arcsin(1.0 / gam[flying])  # Eq. (5)
        # The bed must hit a wall before its parabola falls below the container's lowest
        # point (without gravity: before its straight flight rises above the lid's highest).
        s0, c0 = np.sin(phi0), np.cos(phi0)
        s_max = _flight_span(s0, c0, -1.0, ht + 1.0, gam)
        max_phase = phi0 + s_max + 2.0 * math.pi
        _check_flight(phi0, max_phase, flying, f, x, gam)
        return cls(f=f, x=x, gam=gam, ht=ht, w=w, flying=flying, phi0=phi0, s0=s0, c0=c0,
                   max_phase=max_phase, mode=np.full(n, int(MotionMode.SOLID)),
                   ns=np.full(n, -1), phi_st=nan.copy(), phi_tt=nan.copy(),
                   phi_nd=nan.copy(), dv_st=nan.copy(), dv_nd=nan.copy(),
                   eta=np.full(n, SOLID_LOSS_FACTOR))

    def gap(self, offset: np.ndarray) -> _Gap:
        """The gap between the bed in its flight from the bottom (Eqs. 7 and 9) and the
        bottom (``offset`` 0) or the lid (``offset`` the clearance ``ht``) [strokes]."""
        return _Gap(self.phi0, self.s0, self.c0, 2.0 * self.gam, offset)

    def single_cac(self, i: np.ndarray, bot: np.ndarray) -> None:
        """Single collect-and-collide at the points ``i``, Eqs. (9)-(12)."""
        c0, phi0, gam = self.c0, self.phi0, self.gam
        self.phi_nd[i] = bot[i]
        self.dv_nd[i] = (c0[i] - (bot[i] - phi0[i]) / gam[i]) - np.cos(bot[i])  # Eq. (11)
        ns = np.maximum(np.floor((bot[i] - 0.5 * math.pi) / (2.0 * math.pi)), 0).astype(int)
        self.ns[i] = ns
        self.mode[i] = np.where(ns == 0, int(MotionMode.SINGLE_CAC_HARMONIC),
                                int(MotionMode.SINGLE_CAC_SUBHARMONIC))
        self.eta[i] = self.dv_nd[i] ** 2 / (1.0 + ns) / (2.0 * math.pi)

    def double_cac(self, i: np.ndarray, top: np.ndarray) -> None:
        """Double collect-and-collide at the points ``i``, Eqs. (13)-(18), or scattering."""
        c0, phi0, gam, ht, mode = self.c0, self.phi0, self.gam, self.ht, self.mode
        self.phi_st[i] = top[i]
        self.dv_st[i] = (c0[i] - (top[i] - phi0[i]) / gam[i]) - np.cos(top[i])  # Eq. (16)
        sub_top = top[i] > phi0[i] + 2.0 * math.pi  # subharmonic top impact: scattering
        mode[i[sub_top]] = int(MotionMode.SCATTERING)
        i = i[~sub_top]
        # Eq. (13): pinned to the lid while the lid decelerates faster than g
        phi_tt = self.phi_tt
        phi_tt[i] = np.maximum(top[i], math.pi - phi0[i])
        st, ct = np.sin(phi_tt), np.cos(phi_tt)

        max2 = phi_tt + _flight_span(st + ht, ct, -1.0, ht + 1.0, gam) + 2 * math.pi
        # weak or no gravity: a bed released from the lid almost at rest in the mean frame
        # (phi_tt near 3 pi / 2) drifts above the bottom's sweep (y > 1 stroke) for more than
        # _DRIFT_CYCLES before it can land: it touches the lid again (scattering) or lands
        # as a subharmonic of an order whose eta is below the scattering bed's (Eq. 8);
        # either way it has no repetitive trajectory worth the scan
        y0 = st[i] + ht[i]
        with np.errstate(invalid="ignore"):
            drift = (y0 > 1.0) & ~(_flight_span(y0, ct[i], 1.0, np.inf, gam[i])
                                   <= 2.0 * math.pi * _DRIFT_CYCLES)
        mode[i[drift]] = int(MotionMode.SCATTERING)
        i = i[~drift]
        act = np.zeros(self.f.size, bool)
        act[i] = True
        _check_flight(phi_tt, max2, act, self.f, self.x, gam)
        # the flight from the lid, Eq. (14) (the bed's bottom coordinate), to the bottom
        # and to the lid
        bot2 = _first_crossing(_Gap(phi_tt, st + ht, ct, 2.0 * gam, np.zeros_like(ht)),
                               phi_tt, act, max2, rising=False)
        # leave the lid just after release: a renewed lid contact first means no repetition
        top2 = _first_crossing(_Gap(phi_tt, st + ht, ct, 2.0 * gam, ht),
                               phi_tt + 1e-9, act, max2, rising=True)
        again = np.isfinite(top2[i]) & (~np.isfinite(bot2[i]) | (top2[i] < bot2[i]))
        mode[i[again]] = int(MotionMode.SCATTERING)
        i = i[~again & np.isfinite(bot2[i])]
        self.phi_nd[i] = bot2[i]
        self.dv_nd[i] = (ct[i] - (bot2[i] - phi_tt[i]) / gam[i]) - np.cos(bot2[i])  # Eq. (17)
        k = np.maximum(np.floor((bot2[i] - 0.5 * math.pi) / (2.0 * math.pi)), 0)
        # corrected Eq. (18): a harmonic bottom impact after the next take-off is scattering;
        # for n_s >= 1 the bed re-launches at almost the regular take-off state (Fig. 4-3ii,
        # "conditionally repetitive"), so the whole cycle counts as subharmonic.
        # (up to the bisection's round-off: without gravity the optimum X = h / pi lands its
        # bottom impact exactly on the next take-off, phi = 2 pi, Eq. 19)
        late = (k == 0) & (bot2[i] > phi0[i] + 2.0 * math.pi + _PHASE_TOL)
        mode[i[late]] = int(MotionMode.SCATTERING)
        i, k = i[~late], k[~late].astype(int)
        self.ns[i] = k
        mode[i] = np.where(k == 0, int(MotionMode.DOUBLE_CAC_HARMONIC),
                           int(MotionMode.DOUBLE_CAC_SUBHARMONIC))
        self.eta[i] = (self.dv_st[i] ** 2 + self.dv_nd[i] ** 2) / (1.0 + k) / (2.0 * math.pi)


@dataclass(frozen=True)
class BedTrajectory:
    """Trajectory of the bed against the container walls for one point (paper Fig. 4).

    Attributes
    ----------
    time
        t [s] from ``t = 0`` (container at mid-stroke moving up) to the bed's return to
        the bottom (or the first impact that ends a repetitive trajectory).
    container_bottom, container_top
        Positions of the bottom wall and of the highest position the bed can reach
        (lid minus bed height), i.e. ``x_c`` and ``x_c + h`` [m].
    bed
        Position of the bed's bottom surface [m].
    mode
        The motion mode of the point.
    """

    time: np.ndarray
    container_bottom: np.ndarray
    container_top: np.ndarray
    bed: np.ndarray
    mode: MotionMode
    response: BedResponse


def bed_trajectory(frequency: float, amplitude: float, clearance: float,
                   gravity: float = STANDARD_GRAVITY, samples: int = 2000) -> BedTrajectory:
    """Bed trajectory until its first bottom impact, as in the paper's Fig. 4.

    >>> tr = bed_trajectory(6.0, 0.015, 0.1)
    >>> tr.mode.label, bool(np.all(tr.bed >= tr.container_bottom - 1e-9))
    ('single_cac_harmonic', True)
    """
    r = bed_response(frequency, amplitude, clearance, 1.0, gravity)
    w = 2.0 * math.pi * frequency
    mode = MotionMode(int(r.mode))
    phi0 = float(r.takeoff_phase)
    phi_st, phi_tt, phi_nd = (float(r.top_impact_phase), float(r.top_release_phase),
                              float(r.bottom_impact_phase))
    if mode is MotionMode.SOLID:
        end = 2.5 * math.pi
    elif math.isfinite(phi_nd):
        end = phi_nd
    else:  # scattering after a top impact: Fig. 4 ends the trajectory at the lid
        end = phi_st
    phi = np.linspace(0.0, end, samples)
    yc = np.sin(phi)
    y = yc.copy()  # resting on the bottom until take-off
    hx = clearance / amplitude
    gam = amplitude * w**2 / gravity if gravity > 0 else math.inf
    if mode is not MotionMode.SOLID:
        fl = phi >= phi0
        s = phi[fl] - phi0
        y[fl] = math.sin(phi0) + math.cos(phi0) * s - s**2 / (2 * gam)
        if math.isfinite(phi_st):
            on_lid = phi >= phi_st
            y[on_lid] = yc[on_lid] + hx
            if math.isfinite(phi_tt):
                fl2 = phi >= phi_tt
                s = phi[fl2] - phi_tt
                y[fl2] = math.sin(phi_tt) + hx + math.cos(phi_tt) * s - s**2 / (2 * gam)
    y = np.clip(y, yc, yc + hx)  # remove round-off at the ends of the flights
    return BedTrajectory(time=phi / w, container_bottom=amplitude * yc,
                         container_top=amplitude * yc + clearance, bed=amplitude * y,
                         mode=mode, response=r)


#: The fidelity that answers where the closed forms' assumptions fail.
FIDELITY_BEYOND_LIMITS = "dem"


def assumption_checks(response: BedResponse, *, count: int, per_layer: int, diameter: float,
                      length: float) -> tuple[np.ndarray, np.ndarray]:
    """Whether the closed forms' assumptions hold at each point of ``response``, and why
    not (docs/analytical.md, "Limits of the closed forms").

    Parameters
    ----------
    response
        The :class:`BedResponse` of the points.
    count, per_layer
        Spheres in the bed and per full lattice layer [-].
    diameter, length
        Sphere diameter and inner container height [m].

    Returns
    -------
    (holds, reasons)
        A bool array and an object array of ``"; "``-joined reasons ("" where they hold),
        of the response's shape; each reason names the fidelity to use there.
    """
    shape = np.shape(response.mode)
    mode = np.asarray(response.mode).ravel()
    h = np.broadcast_to(response.clearance, shape).ravel()
    use = f"use {FIDELITY_BEYOND_LIMITS}"
    common = []
    if count < max(per_layer, 2):
        common.append(f"not a collected bed ({count} sphere(s), less than one layer of "
                      f"{per_layer}: they rebound with their COR); {use}")
    h_geo = length - diameter * count / max(per_layer, 1)
    if count and abs(float(np.max(h)) - h_geo) > 0.05 * h_geo + 1e-6:
        common.append(f"clearance L (1 - n/n_max) = {float(np.max(h)):.3g} m differs from "
                      f"the geometry's L - bed height = {h_geo:.3g} m; {use}")
    reasons = np.empty(mode.size, object)
    for i, c in enumerate(mode):
        r = list(common)
        if c == int(MotionMode.SCATTERING):
            r.append(f"scattering: eta = {SOLID_LOSS_FACTOR:g} is Eq. (8)'s convention, the "
                     f"bed dissipates far more (0.1-0.3); {use} or the plastic bed")
        reasons[i] = "; ".join(r)
    holds = np.array([not s for s in reasons], bool)
    return holds.reshape(shape), reasons.reshape(shape)


#: The fidelities to use where the closed forms' assumptions fail, as legends and summaries
#: name them (a fields map made by the DEM, or the DEM itself).
USE_BEYOND_LIMITS = "fields from a DEM map (--model fields) or dem"

#: Each check of :func:`assumption_checks` by its short name, and the text that opens its
#: reason.
ASSUMPTION_KINDS = {"collected_bed": "not a collected bed",
                    "clearance": "clearance L (1 - n/n_max)",
                    "scattering": "scattering:"}


def assumption_kinds(reason: str) -> list[str]:
    """The short names (:data:`ASSUMPTION_KINDS`) of the checks that failed in ``reason``
    (one entry of :func:`assumption_checks`' reasons; [] where they hold)."""
    return [k for k, opening in ASSUMPTION_KINDS.items() if opening in str(reason)]


def assumption_summary(holds, reasons) -> dict:
    """How many of the points ``holds`` / ``reasons`` (:func:`assumption_checks`, any
    shape; the caller leaves out points without an answer) rest on failed assumptions.

    Returns
    -------
    dict
        ``points`` (all), ``flagged`` (where they fail), ``reasons`` (flagged points per
        check of :data:`ASSUMPTION_KINDS`, only those that occur), ``reason`` (the text of
        each occurring check, from its first flagged point) and ``use`` (the fidelities to
        use there, :data:`USE_BEYOND_LIMITS`).
    """
    ok = np.asarray(holds, bool).ravel()
    why = np.asarray(reasons, object).ravel()
    counts: dict[str, int] = {}
    text: dict[str, str] = {}
    for r in why[~ok]:
        for part in re.split(r";\s*use [^;]*;?\s*", str(r)):  # each check's own text
            for k in assumption_kinds(part):
                text.setdefault(k, part.strip())
        for k in assumption_kinds(r):
            counts[k] = counts.get(k, 0) + 1
    return {"points": int(ok.size), "flagged": int((~ok).sum()), "reasons": counts,
            "reason": text, "use": USE_BEYOND_LIMITS}


def assumption_line(summary: dict, what: str = "points") -> str | None:
    """One line of text from :func:`assumption_summary` (None where every point holds)."""
    if not summary.get("flagged"):
        return None
    kinds = ", ".join(f"{k.replace('_', ' ')} {n}" for k, n in summary["reasons"].items())
    return (f"analytic assumptions fail at {summary['flagged']} of {summary['points']} "
            f"{what} ({kinds}): use {summary['use']} there")
