"""The example scenario: a commented scenario file with every section, every key and its
default (``pdamper example-scenario``, :data:`pdamper.io.scenario.EXAMPLE_SCENARIO`).

:func:`example_text` writes it from the defaults of :class:`~pdamper.io.scenario.Scenario`,
which the scenario module hands in when the text is first asked for (it formats every
quantity with its unit, which needs the unit registry, and most commands never print it);
:func:`pdamper.io.scenario.example_scenario` is that text parsed, and equals the defaults
(a test holds it).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pdamper.contact.law import DAMPING_MODELS
from pdamper.models.settings import PAPER_CYCLES
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.units import format_quantity

if TYPE_CHECKING:  # pragma: no cover
    from pdamper.io.scenario import BeamSpec, Scenario

_BEAM, _TIP = paper.paper_beam()


def example_text(s: Scenario, beam: BeamSpec) -> str:
    """The text of ``EXAMPLE_SCENARIO``: every section with its defaults ``s`` (a default
    :class:`~pdamper.io.scenario.Scenario`; ``beam`` the default ``[structure] beam``),
    commented."""
    return _example_levels(s, beam) + _example_study(s) + _example_dem(s)


def _example_levels(s: Scenario, beam: BeamSpec) -> str:
    """The example's head and its Level II and III sections (damper, excitation,
    structure)."""
    c, p, x, st = s.container, s.particles, s.excitation, s.structure
    q = format_quantity
    return f"""\
# pdamper scenario: the reference paper's benchmark damper on its beam-like structure.
# Every quantity carries its unit ("120 mm", "10 Hz", "7900 kg/m^3"); bare numbers are SI.
# Every section and key is optional; what is left out takes the value shown here.
title = "{s.title}"

[container]                 # cuboid particle container, inner dimensions
length = "{q(c.length, 'mm')}"           # along the excitation (vertical), L in h = L (1 - n_p/n_max)
width = "{q(c.width, 'mm')}"
depth = "{q(c.depth, 'mm')}"
material = "{c.material}"            # a library name (docs/materials.md: "S235", "POM", ...) or inline:
# material = {{ name = "my PMMA", youngs_modulus = "3.2 GPa", poisson_ratio = 0.35,
#              density = "1190 kg/m^3", yield_strength = "70 MPa" }}   # (one line in TOML)
mass = "{q(c.mass, 'kg')}"               # m_con, subtracted in Eq. (4) when a driving force includes it

[particles]
count = {p.count}                  # n_p; at most n_max (16 per layer x 12 layers = 192 here)
radius = "{q(p.radius, 'mm')}"
material = "{p.material}"
friction = {p.friction}              # sliding friction coefficient mu of every contact (DEM)
# friction = "0.1 +- 0.03"  # a value with its standard deviation (also lengths, masses, ...):
#                           # --uncertainty N samples it (docs/design.md)

[excitation]                # Level II: x_c = X sin(2 pi f t)
frequency = "{q(x.frequency, 'Hz')}"
amplitude = "{q(x.amplitude, 'mm')}"         # stroke X
gravity = "{q(x.gravity, 'm/s^2')}"        # g; "0 m/s^2" for a structure in orbit (analytic and DEM)

[structure]                 # Level III: M x'' + D x' + K x = F (Eq. 23)
# mass = "{q(paper.PAPER_MASS, 'kg')}"       # default K / (2 pi {paper.PAPER_EIGENFREQUENCY} Hz)^2: \
the printed {paper.PAPER_PRINTED_MASS} kg is inconsistent
stiffness = "{q(st.stiffness, 'N/m')}"
damping = "{q(st.damping, 'kg/s')}"
initial_displacement = "{q(st.initial_displacement, 'mm')}"   # at the damper's point
# Instead of mass, stiffness and damping (leave those out), N modes (docs/structure.md):
# modes = "modes.csv"       # one row per mode, unit headers (relative to this file):
#                           # frequency [Hz], damping ratio [1], damper [kg^-0.5](, observation [kg^-0.5])
#                           # (, load [kg^-0.5]: where forces act; default the damper's point)
# or the Timoshenko cantilever of Sect. 4.1 (every key optional; defaults: the paper's beam):
# beam = {{ length = "{q(_BEAM.length, 'mm')}", width = "{q(_BEAM.width, 'mm')}", \
height = "{q(_BEAM.height, 'mm')}", youngs_modulus = "{q(_BEAM.youngs_modulus, 'GPa')}", \
poisson_ratio = {_BEAM.poisson_ratio}, density = "{q(_BEAM.density, 'kg/m^3')}", \
elements = {_BEAM.elements}, tip_mass = "{q(_TIP.mass, 'kg')}", modes = 3, \
damper_position = "{q(_BEAM.length, 'mm')}", observation_position = "{q(_BEAM.length, 'mm')}", \
damping_ratio = {beam.damping_ratio:.4g} }}
#   (material = "S235" instead of youngs_modulus, poisson_ratio, density; damping_ratio: one
#   for all modes or a list, one per mode; positions from the clamp, default the tip)

"""


def _example_study(s: Scenario) -> str:
    """The example's sections of the simulation, the design study, the fields and the map."""
    q = format_quantity
    return f"""\
[simulation]
model = "{s.simulation.model}"          # damper fidelity: "analytic" (model 3), "fields" (2), "dem" (1)
duration = "{q(s.simulation.duration, 's')}"
sample_rate = "{q(s.simulation.sample_rate, 'Hz')}"     # of the stored trajectory

[optimization]
at = "{q(s.optimization.at, 's')}"                # objective: amplitude at this time after release
# step = 16                 # particle-count increment; default one layer
objective = "{s.optimization.objective}"    # or "settling-time", "mean-damping" (maximised)
# vary = ["particles=16:176:16", "radius=3mm:6mm:4"]   # design study; default: the count
method = "{s.optimization.method}"             # "grid" (brute force), "optimize" (scipy), or by size
# threshold = "14.5 mm"     # settling-time threshold; default |x0| / 4
workers = "{s.optimization.workers}"            # dask workers; "auto": 0 (in-process) for cheap models
max_evaluations = {s.optimization.max_evaluations}     # budget of the optimiser
max_grid = {s.optimization.max_grid}            # largest grid "auto" evaluates by brute force
seed = {s.optimization.seed}                    # seed of the optimiser
tolerance = "{s.optimization.tolerance * 100:g}%"              # lightest design this close to the best

[fields]                    # options of the effective-field model ("--model fields")
# file = "map.nc"           # map from `pdamper map` (relative to this file)
extrapolation = "{s.fields.extrapolation}"     # outside the map: "error", "clamp" or "analytic"
interpolate = "{s.fields.interpolate}"   # or "dissipated_energy"
nonstationary = "{s.fields.nonstationary}"      # non-stationary cells: "mask" (holes) or "use"
strict = {str(s.fields.strict).lower()}               # a map of another geometry is an error

[map]                       # Level II grids: "start:stop:count", "log:start:stop:count" or one value
frequency = "{s.map.frequency}"
amplitude = "{s.map.amplitude}"
# particles = "16:96:6"     # a particle-count axis (default: the one count of [particles])
dem_frequency = "{s.map.dem_frequency}"      # grid of the DEM map in "pdamper paper"
dem_amplitude = "{s.map.dem_amplitude}"
dem_packing = "{s.map.dem_packing}"           # initial packing of a map's DEM runs ("lattice",
                            # "random", "auto": random where it fits, else the lattice;
                            # the lattice's symmetric states are artefacts)

"""


def _example_dem(s: Scenario) -> str:
    """The example's sections of the DEM and the COR models."""
    q = format_quantity
    dem = s.dem
    _MODELS = " or ".join(f'"{m}"' for m in DAMPING_MODELS)  # noqa: N806
    return f"""\
[dem]                       # options of the DEM model ("pdamper dem", "--model dem")
integrator = "{dem.integrator}"         # "gear" (variable step, the paper's), "verlet", or "auto"
                            # (gear, handing over to verlet in jammed beds; docs/dem.md)
cycles = "{dem.cycles}"               # Level II: "auto" runs until the loss factor is steady;
                            # a number runs that many cycles (the paper: {PAPER_CYCLES})
skip_cycles = {dem.skip_cycles}             # cycles never averaged (complex power, Eqs. 1-4)
max_cycles = {dem.max_cycles}             # upper bound of a run until steady
window_cycles = {dem.window_cycles}           # steady: steady_windows windows of window_cycles cycles
steady_windows = {dem.steady_windows}          # whose loss factors agree within max(steady_rtol |eta|,
steady_rtol = {dem.steady_rtol}           # steady_atol), no trend, no symmetric lattice state
                            # (docs/fields.md)
steady_atol = {dem.steady_atol}
quiet_window_cycles = {dem.quiet_window_cycles}     # a quiet bed (cycle-to-cycle scatter below
quiet_scatter = {dem.quiet_scatter}         # quiet_scatter x the tolerance) is judged on
quiet_windows = {dem.quiet_windows}           # quiet_windows windows of quiet_window_cycles cycles
quiet_skip_cycles = {dem.quiet_skip_cycles}       # after min(quiet_skip_cycles, skip_cycles) cycles
                            # (quiet_window_cycles = 0: never; docs/fields.md)
# restitution_pp = {dem.restitution_pp}      # constant sphere-sphere COR (default; or [restitution])
# restitution_pw = {dem.restitution_pw}     # constant sphere-wall COR (default; or [restitution])
damping_model = "{dem.damping_model}"     # damping law of the normal force: {_MODELS}
# min_impact_velocity = "0.01 m/s"  # onset-speed floor of the exact/gonthier damping
# friction_model = "regularised"  # or "spring" (tangential spring, Coulomb limit; verlet/auto)
packing = "{dem.packing}"         # "lattice" (the paper's 4 x 4 layers), "random" or "auto"
seed = {dem.seed}                    # seed of the random packing (recorded always)
safety = {dem.safety}               # time step / Hertz contact time
sample_rate = "{q(dem.sample_rate, 'Hz')}"     # of the force and container series
# snapshot_rate = "200 Hz"  # particle snapshots per second (default: first and last)
error_estimate = {str(dem.error_estimate).lower()}     # estimate the integration error of eta and m_eff
                            # from a refined companion run (~2x the cost; docs/dem.md)
accuracy = {dem.accuracy.accuracy}             # its target (relative); a run missing it is redone
max_refinements = {dem.max_refinements}         # refined, at most this many times
gear_free_flight = {str(dem.gear_free_flight).lower()}    # Gear steps only spheres that may touch something,
                            # the others fly their exact parabola (docs/dem.md)
transient_tolerance = {dem.transient_tolerance}  # Gear tolerance of the start from rest (the cycles no
                            # window averages; 1e-5, Gear's own: none; docs/fields.md)

[restitution]               # COR model of each pair (Level I, docs/restitution.md), instead of the
                            # [dem] constants above (a pair given in both places is an error)
# particle_particle = "paper"                  # the paper's Fig. 2 curve (reconstructed from its text)
# particle_wall = 0.85                         # a constant
# particle_wall = "thornton"                   # Thornton 1997 from the materials' yield strength
# particle_wall = {{ model = "table", file = "cor.csv" }}   # rows "velocity [m/s], cor [-], std [-]"
# particle_wall = {{ model = "table", file = "cor.csv", fit = "exponential" }}  # "thornton", "linear"
# particle_wall = {{ model = "paper", scale = 1.5 }}        # e -> 1 - 1.5 (1 - e)
"""
