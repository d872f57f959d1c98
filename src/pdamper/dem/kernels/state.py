"""Named bundles of the state that the DEM kernels share.

Immutable inputs travel as :class:`typing.NamedTuple` bundles (numba compiles field access
to a plain load: no cost over positional tuples); what a kernel updates in place and must
keep between calls (the run state, the ledger, the statistics) lives in one-element numpy
structured arrays (numba *records*), so that a run can be advanced in chunks and resumed
bit-identically. The hot loops copy record fields into locals and write them back at the
end of a call.

Everything is SI: lengths [m], times [s], velocities [m/s], forces [N], energies [J].
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

# ---- codes -------------------------------------------------------------------------
#: Container motion kinds (:class:`Drive.kind`).
MOTION_HARMONIC = 0
MOTION_TABLE = 1
MOTION_STRUCTURE = 2

#: Error codes (``stats.error``) of a failed run.
ERR_NONE = 0
ERR_NAN = 1
ERR_OVERLAP = 2
ERR_ESCAPE = 3
ERR_LIST = 4
ERR_ENERGY = 5
ERR_SPEED = 6


# ---- immutable inputs --------------------------------------------------------------
class World(NamedTuple):
    """Container box, gravity and the linked-cell grid of the contact search."""

    lx: float
    ly: float
    lz: float
    gravity: float
    skin: float
    cell: float
    ncx: int
    ncy: int
    ncz: int


class Law(NamedTuple):
    """Scalars of the contact law (:class:`pdamper.contact.law.ContactParameters`)."""

    model: int          # damping model code (pdamper.contact.forces.DAMPING_*)
    nmat: int           # number of particle materials
    v_reg: float        # regularisation velocity of the tanh friction law [m/s]
    v_min: float        # floor of the onset speed that sets the damping [m/s]
    reimpact: float     # re-impact factor of persisting contacts [-]


class Particles(NamedTuple):
    """Per-particle constants."""

    rad: np.ndarray          # radius [m]
    mass: np.ndarray         # [kg]
    inertia: np.ndarray      # moment of inertia [kg m^2]
    kwall: np.ndarray        # Hertz stiffness against the wall [N/m^1.5]
    pmat: np.ndarray         # material index (int)
    inv_mass: np.ndarray     # 1 / mass
    inv_inertia: np.ndarray  # 1 / inertia


class PairTypes(NamedTuple):
    """Per material-pair type: sphere pair ``a * nmat + b``, sphere of material ``a`` on
    the walls ``nmat^2 + a``."""

    estar: np.ndarray   # effective modulus E* [Pa]
    mu: np.ndarray      # friction coefficient [-]
    cor_v: np.ndarray   # COR curve nodes: impact speeds [m/s], (npair, nmax)
    cor_e: np.ndarray   # COR curve nodes: COR [-], (npair, nmax)
    cor_n: np.ndarray   # nodes used per pair type (int)
    memo: np.ndarray    # (npair, 2): last (COR, damping factor), see onset_damping_cached
    gstar: np.ndarray = np.zeros(0)  # effective shear modulus G* [Pa] (the spring law's)


class PairContacts(NamedTuple):
    """Half Verlet list (pairs i < j, sorted per particle) with the contact history."""

    start: np.ndarray   # (n + 1,) first entry of particle i
    j: np.ndarray       # partner index
    active: np.ndarray  # 1 while in contact (int)
    k: np.ndarray       # Hertz stiffness fixed at the onset [N/m^1.5]
    d: np.ndarray       # damping parameter of the normal force
    v0: np.ndarray      # impact speed [m/s]
    #: (cap, 4) the spring friction law's elastic tangential displacement [m] (3) and
    #: damping factor ``2 sqrt(5/6) |beta|`` [-] per entry; (0, 4) under the tanh law
    xi: np.ndarray = np.zeros((0, 4))


class Neighbours(NamedTuple):
    """The Verlet list in use, a spare one that a rebuild fills, and the search grid."""

    pairs: PairContacts
    spare: PairContacts
    head: np.ndarray       # (ncells,) first particle of each cell
    nxt: np.ndarray        # (n,) next particle in the same cell
    pos_build: np.ndarray  # (n, 3) positions at the last build


class WallContacts(NamedTuple):
    """History of the sphere-wall contacts, (n, 6) with walls -x, +x, -y, +y, floor, lid,
    and a log of the contacts that start in one force evaluation (pair entry ``b`` or
    ``-(6 i + wall) - 1``), so that a rejected Gear step can undo them."""

    active: np.ndarray
    d: np.ndarray
    v0: np.ndarray
    onset_log: np.ndarray
    #: (6 n, 4), row ``6 i + wall``: as :attr:`PairContacts.xi`; (0, 4) under the tanh law
    xi: np.ndarray = np.zeros((0, 4))


class Drive(NamedTuple):
    """Container motion: harmonic ``z0 + X sin(W t)``, a sampled table, or a 1-DOF
    structure ``M a = -K z - D v + F_z``; a structure under a load history (``loaded``
    = 1) holds the base position, base velocity and external force in the tables.

    A structure of ``nmodes > 0`` mass-normalised modes replaces the 1-DOF
    (:mod:`pdamper.dem.kernels.modes`): the ``m_*`` arrays hold its constants (one value
    per mode) and its state, updated in place; under a load history ``table_b`` holds
    the base acceleration."""

    kind: int
    z0: float
    amplitude: float
    omega: float
    table_dt: float
    table_z: np.ndarray
    table_v: np.ndarray
    table_a: np.ndarray
    mass: float
    damping: float
    stiffness: float
    loaded: int
    nmodes: int = 0                       # 0: the 1-DOF; N: N modes
    m_w2: np.ndarray = np.zeros(0)        # w_j^2 [1/s^2]
    m_c: np.ndarray = np.zeros(0)         # 2 zeta_j w_j [1/s]
    m_phi: np.ndarray = np.zeros(0)       # mode shapes at the container [1/sqrt(kg)]
    m_load: np.ndarray = np.zeros(0)      # mode shapes at the load point [1/sqrt(kg)]
    m_gamma: np.ndarray = np.zeros(0)     # participation of a base translation [sqrt(kg)]
    m_weight: np.ndarray = np.zeros(0)    # Gear error weight of each mode [1/sqrt(kg)]
    table_b: np.ndarray = np.zeros(2)     # base acceleration table [m/s^2]
    m_state: np.ndarray = np.zeros((3, 0))    # (q, q', q'') (updated in place)
    m_nord: np.ndarray = np.zeros((6, 0))     # Gear Nordsieck vectors of the modes
    m_backup: np.ndarray = np.zeros((6, 0))   # their backup (Verlet: scratch)
    m_samples: np.ndarray = np.zeros((0, 0))  # (q, q', q'') at the samples (samples, 3N)


class Stepping(NamedTuple):
    """Time grid and step control of one phase (settling or excitation)."""

    t0: float            # start time [s]
    half: float          # half the sample interval: the landing grid [s]
    nsamp: int           # samples of the phase (landings: 2 (nsamp - 1))
    snap_every: int      # a snapshot every this many samples (0: none)
    dt: float            # Verlet step, or the first Gear step [s]
    dt_min: float        # Gear bounds [s]
    dt_max: float
    dt_contact: float    # lower bound of the time-to-contact limit [s]
    h_cap: float         # Gear: the friction cap is never evaluated below this step [s]
    tol: float           # Gear local error tolerance [-]
    v_scale: float       # Gear velocity scale of the error norm [m/s]
    adaptive: int        # Gear: 1 variable step, 0 fixed
    contact_bound: int   # Gear: 1 bounds the step by the time to the next contact
    v_design: float      # impact speed for which dt_design resolves the contact [m/s]
    dt_design: float     # safety x Hertz contact time at v_design [s]
    follow_impacts: int  # 1: a faster impact shrinks the step (at the next sample)
    v_limit: float       # particle speeds beyond this are a blow-up [m/s]
    max_overlap: float   # overlap / radius beyond this stops the run [-] (inf: never)
    free_flight: int     # Gear: 1 takes spheres that cannot touch anything out of the step


class Work(NamedTuple):
    """Force and torque of the last evaluation, and the predicted velocities."""

    frc: np.ndarray      # (n, 3) total force, gravity included [N]
    trq: np.ndarray      # (n, 3) torque [N m]
    vel_pred: np.ndarray  # (n, 3) velocities used in the velocity-dependent forces
    omg_pred: np.ndarray  # (n, 3)


class Flights(NamedTuple):
    """Free flights of the Gear kernel (:mod:`pdamper.dem.kernels.flights`): a sphere
    that cannot touch anything before ``until`` leaves the step and moves on its parabola
    from ``(x0, v0)`` at ``t0``; the others are stepped."""

    free: np.ndarray    # (n,) int: 1 while in free flight
    x0: np.ndarray      # (n, 3) position at the start of the flight [m]
    v0: np.ndarray      # (n, 3) velocity at the start of the flight [m/s]
    t0: np.ndarray      # (n,) start of the flight [s]
    until: np.ndarray   # (n,) no contact of the sphere is possible before this time [s]
    vlim: np.ndarray    # (n,) speed in the free-fall frame the horizons assume the sphere
    #                     keeps below [m/s]
    vown: np.ndarray    # (n,) its (constant) speed in that frame in free flight [m/s]
    act: np.ndarray     # (n,) int: the stepped spheres, the first ``count[0]`` entries
    count: np.ndarray   # (1,) int
    scal: np.ndarray    # (7,) float: earliest ``until`` [s], container speed limit [m/s],
    #                     steps between periodic regroups, the free-fall frame's velocity
    #                     U [m/s] (3) and time [s] of the last regroup


class Nordsieck(NamedTuple):
    """Gear state: ``(x, h v, h^2 a / 2, ...)`` of the positions (6, n, 3), of the angular
    velocities (5, n, 3) and of the structure (6,), with a backup of the latter."""

    x: np.ndarray
    w: np.ndarray
    c: np.ndarray
    c_backup: np.ndarray


class Samples(NamedTuple):
    """Sampled time series (one row per sample)."""

    time: np.ndarray
    zc: np.ndarray
    vc: np.ndarray
    ac: np.ndarray
    force: np.ndarray            # (ns, 3) window mean of the force on the container
    com: np.ndarray              # (ns, 3) centre of mass
    kinetic: np.ndarray
    rotational: np.ndarray
    potential: np.ndarray
    elastic: np.ndarray
    dissipated_normal: np.ndarray
    dissipated_friction: np.ndarray
    container_work: np.ndarray


class Snapshots(NamedTuple):
    """Particle snapshots, (nq, n, 3) each."""

    pos: np.ndarray
    vel: np.ndarray
    omg: np.ndarray


class Rates(NamedTuple):
    """What one force evaluation returns besides forces and torques."""

    fx: float     # force of the particles on the container [N]
    fy: float
    fz: float
    dn: float     # power dissipated by the normal damping [W]
    df: float     # power dissipated by friction [W]
    wc: float     # power of the container walls on the particles [W]
    eel: float    # elastic energy [J]
    ovl: float    # largest overlap / radius [-]
    ttc: float    # shortest time to a new contact [s] (if asked for)
    vmax: float   # largest particle speed [m/s]
    vimp: float   # fastest impact (approach speed at an onset or re-impact) [m/s]


# ---- mutable records ---------------------------------------------------------------
#: Integrator state kept between the chunks of a run.
RUN_STATE = np.dtype([
    ("t", np.float64), ("t_win", np.float64),          # time, start of the force window
    ("zc", np.float64), ("vc", np.float64), ("ac", np.float64),  # container
    ("h", np.float64), ("h_des", np.float64), ("le_prev", np.float64),  # Gear control
    ("disp", np.float64),                               # Verlet rebuild bound [m]
    ("ttc", np.float64), ("vmax", np.float64),          # of the last force evaluation
    ("dt", np.float64), ("v_design", np.float64),       # step and the impact speed it
    ("h_cap", np.float64), ("dt_min", np.float64),      # is designed for; Gear bounds
    ("t_base", np.float64),                             # time of the last step change
    ("step", np.int64), ("countdown", np.int64),        # Verlet steps since t_base, to landing
    ("j_base", np.int64),                               # landing of the last step change
    ("landing", np.int64),                              # landings done
])

#: Running integrals (trapezoidal) and the rates of the last step.
LEDGER = np.dtype([
    ("dn", np.float64), ("df", np.float64), ("wc", np.float64),        # [J]
    ("imp_x", np.float64), ("imp_y", np.float64), ("imp_z", np.float64),  # impulse [N s]
    ("p_dn", np.float64), ("p_df", np.float64), ("p_wc", np.float64),
    ("p_fx", np.float64), ("p_fy", np.float64), ("p_fz", np.float64),
])

#: Counters and extremes of a phase, and the cause of a failure.
STATS = np.dtype([
    ("steps", np.int64), ("rebuilds", np.int64), ("onsets", np.int64),
    ("rejects", np.int64), ("error", np.int64),
    ("t_error", np.float64), ("error_value", np.float64), ("max_overlap", np.float64),
    ("max_impact", np.float64), ("dt_lo", np.float64), ("dt_hi", np.float64),
    ("stepped", np.int64), ("regroups", np.int64),      # Gear: sphere-steps, regroups
    ("gear_steps", np.int64),
])


def record(dtype: np.dtype) -> np.ndarray:
    """A zeroed one-element structured array (a numba record in the kernels)."""
    return np.zeros(1, dtype)


def empty_pair_contacts(n: int, cap: int, spring: bool = False) -> PairContacts:
    """A Verlet list of capacity ``cap`` for ``n`` spheres; ``spring``: with the tangential
    displacements of the spring friction law."""
    return PairContacts(np.zeros(n + 1, np.int64), np.zeros(cap, np.int64),
                        np.zeros(cap, np.int64), np.zeros(cap), np.zeros(cap), np.zeros(cap),
                        np.zeros((cap if spring else 0, 4)))


def empty_flights(n: int) -> Flights:
    """Flights of ``n`` spheres, all stepped."""
    return Flights(np.zeros(n, np.int64), np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n),
                   np.zeros(n), np.zeros(n), np.zeros(n), np.arange(n, dtype=np.int64),
                   np.array([n], np.int64), np.array([np.inf, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]))


def empty_samples(nsamp: int) -> Samples:
    z = [np.zeros(nsamp) for _ in range(13)]
    z[4] = np.zeros((nsamp, 3))
    z[5] = np.zeros((nsamp, 3))
    return Samples(*z)


def empty_snapshots(nsnap: int, n: int) -> Snapshots:
    return Snapshots(np.zeros((nsnap, n, 3)), np.zeros((nsnap, n, 3)), np.zeros((nsnap, n, 3)))
