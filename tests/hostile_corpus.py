"""Hostile-but-realistic inputs, including the ones the fuzzers found, as data.

Each case is one ``pdamper`` invocation and what it must answer: ``OK`` (exit 0, finite
JSON when ``--json`` is given) or ``Error(field)`` (exit 2, exactly one line on stderr,
``error: <field>...``). Arguments may name paths under the test's temporary directory with
``{tmp}``; a temporary directory holds a directory ``dir``, a regular file ``file``, a FIFO
``fifo``, a scenario for every ``SCENARIOS`` entry (``{scenario:NAME}``) and every
``FILES`` entry under its name (COR tables, measured records).

The corpus runs as ordinary tests (``tests/cli/test_corpus.py``); the fuzz suite
(``tests/fuzz``) adds what it finds here.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class OK:
    """Exit status 0 (and finite JSON with ``--json``)."""


@dataclass(frozen=True)
class Error:
    """Exit status 2 and one line ``error: <field>...`` on stderr."""

    field: str


#: Scenario files of the corpus, by name.
SCENARIOS = {
    "radius_1um": '[particles]\nradius = "1 um"\n',
    "map_empty_stop": '[map]\nfrequency = "2Hz::5"\n',
    "map_no_count": '[map]\namplitude = "1mm:200mm"\n',
    "map_not_text": "[map]\nfrequency = 5\n",
    "material_unknown_key": '[particles]\nmaterial = { name = "glass", youngs_modulus = '
                            '"63 GPa", poisson_ratio = 0.2, density = "2500 kg/m^3", '
                            'colour = "green" }\n',
    "material_poisson_half": '[particles]\nmaterial = { name = "x", youngs_modulus = "3 GPa",'
                             ' poisson_ratio = 0.5, density = "1000 kg/m^3" }\n',
    "material_negative_density": '[container]\nmaterial = { name = "x", youngs_modulus = '
                                 '"3 GPa", poisson_ratio = 0.3, density = "-1000 kg/m^3" }\n',
    "material_missing_key": '[particles]\nmaterial = { name = "x", youngs_modulus = "3 GPa",'
                            ' poisson_ratio = 0.3 }\n',
    "material_modulus_unitless": '[particles]\nmaterial = { name = "x", youngs_modulus = '
                                 '"GPa", poisson_ratio = 0.3, density = "1000 kg/m^3" }\n',
    "sample_rate_huge": '[dem]\nsample_rate = "1e12 Hz"\n',
    "duration_huge": '[simulation]\nduration = "1e9 s"\n',
    "frequency_decorated": '[excitation]\nfrequency = "10Hz🙂"\n',
    "glass": '[particles]\nmaterial = { name = "glass", youngs_modulus = "63 GPa", '
             'poisson_ratio = 0.2, density = "2500 kg/m^3" }\n',
    # -- COR tables in runs, meaningless inputs (block: tables, scales, choices, formats)
    "cor_table": '[restitution]\nparticle_wall = { model = "table", file = "cor.csv" }\n'
                 'particle_particle = { model = "table", file = "cor.csv" }\n',
    "cor_table_small_map": '[particles]\ncount = 4\n[dem]\ncycles = 2\nskip_cycles = 1\n'
                           'integrator = "verlet"\n[restitution]\n'
                           'particle_wall = { model = "table", file = "cor.csv" }\n',
    "cor_table_too_fast": '[restitution]\nparticle_wall = { model = "table", '
                          'file = "cor_1e305.csv" }\n',
    "four_spheres": '[particles]\ncount = 4\n[dem]\nintegrator = "verlet"\n',
    # -- counts judged before they are built; physics limits on every run
    "vary_particles_huge": '[optimization]\nvary = ["particles=0:1000000000:1"]\n',
    "count_16": "[particles]\ncount = 16\n",
    # -- the user's structure: [structure] modes (CSV) and beam
    "modes_one": '[structure]\nmodes = "modes_one.csv"\n',
    "modes_and_beam": '[structure]\nmodes = "modes_one.csv"\nbeam = { modes = 2 }\n',
    "modes_and_stiffness": '[structure]\nmodes = "modes_one.csv"\nstiffness = "1000 N/m"\n',
    "beam_damper_beyond_tip": '[structure]\nbeam = { damper_position = "2 m" }\n',
    "beam_elements_huge": "[structure]\nbeam = { elements = 100000000 }\n",
    "beam_modes_too_many": "[structure]\nbeam = { elements = 3, modes = 50 }\n",
    "beam_three_modes": "[structure]\nbeam = { modes = 3, elements = 20 }\n",
    # -- gravity
    "gravity_inf": "[excitation]\ngravity = inf\n",
    # -- input uncertainty: "value +- sd" in a scenario
    "uncertain_friction": '[particles]\nfriction = "0.1 +- 0.03"\n',
    "uncertain_friction_negative_sd": '[particles]\nfriction = "0.1 +- -0.03"\n',
    "uncertain_length_no_unit_sd": '[container]\nlength = "120 mm +- 0.1"\n',
    "uncertain_count": '[particles]\ncount = "64 +- 2"\n',
    "uncertain_short_run": '[particles]\nfriction = "0.1 +- 0.03"\n[simulation]\n'
                           'duration = "0.5 s"\n',
    # -- load histories: [load]
    "load_force": '[load]\nforce = "load_force.csv"\ntail = "0.5 s"\n',
    "load_both": '[load]\nforce = "load_force.csv"\nbase_acceleration = "load_acc.csv"\n',
    "load_tail_negative": '[load]\nforce = "load_force.csv"\ntail = "-1 s"\n',
    # -- realisations: a random packing (several realisations)
    "dem_random": '[dem]\npacking = "random"\n',
    # -- forced response (frf): loads, frequency grids, structures
    "frf_dem_three_modes": '[simulation]\nmodel = "dem"\n[structure]\n'
                           'beam = { modes = 3, elements = 20 }\n',
    # -- degenerate values: undamped and overdamped structures, loads below any measurement
    "undamped": '[structure]\ndamping = "0 kg/s"\n',
    "overdamped": '[structure]\ndamping = "1e9 kg/s"\n',
    "undamped_peak_frf": '[structure]\ndamping = "0 kg/s"\n[optimization]\n'
                         'objective = "peak-frf"\n',
    "frf_load_tiny": '[optimization]\nobjective = "peak-frf"\nfrf_load = "1e-200 N"\n',
    # -- every design objective in a report and with --plot
    "study_rms_load": '[load]\nforce = "load_force.csv"\n[optimization]\nobjective = "rms"\n'
                      'vary = ["particles=0:32:32"]\n',
    "study_peak_frf": '[optimization]\nobjective = "peak-frf"\nband = "4Hz:7Hz:3"\n'
                      'vary = ["particles=0:32:32"]\n',
    # -- COR fit uncertainty through the DEM (--uncertain restitution.PAIR=fit)
    "cor_fit_small": '[particles]\ncount = 4\n[dem]\ncycles = 2\nskip_cycles = 1\n'
                     '[restitution]\nparticle_wall = { model = "table", file = "cor.csv", '
                     'fit = "linear" }\n',
}


def _free_decay(unit: str) -> str:
    """A measured free decay of the 58 mm release (5.56 Hz, zeta 0.03) in ``unit``."""
    import math

    w = 2 * math.pi * 5.56
    rows = (f"{k * 1e-3:.3f}, {-58.0 * math.exp(-0.03 * w * k * 1e-3) * math.cos(w * k * 1e-3):.4f}\n"
            for k in range(2000))
    return f"time [s], displacement [{unit}]\n" + "".join(rows)


#: Further files of the corpus' temporary directory, by name.
FILES = {
    "cor.csv": "velocity [m/s], cor [-], std [-]\n0.20, 0.89, 0.01\n0.60, 0.86, 0.01\n"
               "1.80, 0.80, 0.02\n",
    "cor_1e305.csv": "velocity [m/s], cor [-]\n0.2, 0.89\n1e300, 0.85\n1e305, 0.80\n",
    "decay_mm.csv": _free_decay("mm"),
    "decay_furlong.csv": _free_decay("furlong"),
    # -- the user's structure: modes files
    "modes_one.csv": "frequency [Hz], damping ratio [1], damper [kg^-0.5]\n5.56, 0.0052, 0.81\n",
    "modes_no_unit.csv": "frequency, damping ratio [1], damper [kg^-0.5]\n5.56, 0.0052, 0.81\n",
    "modes_nan.csv": "frequency [Hz], damping ratio [1], damper [kg^-0.5]\n5.56, nan, 0.81\n",
    "modes_negative_frequency.csv": "frequency [Hz], damping ratio [1], damper [kg^-0.5]\n"
                                    "-5.56, 0.0052, 0.81\n",
    "modes_shape_in_metres.csv": "frequency [Hz], damping ratio [1], damper [m]\n5.56, 0.0052, 0.81\n",
    "modes_header_only.csv": "frequency [Hz], damping ratio [1], damper [kg^-0.5]\n",
    # -- load histories: --load / --base-acceleration files
    "load_force.csv": "# 2 N at 5 Hz\ntime [ms], force [N]\n" + "".join(
        f"{5 * k}, {2 * __import__('math').sin(2 * __import__('math').pi * 5 * k * 5e-3):.5f}\n"
        for k in range(401)),
    "load_acc.csv": "time [s]; acceleration [g0]\n" + "".join(
        f"{k * 5e-3:.3f}; {0.1 * __import__('math').sin(2 * __import__('math').pi * 5 * k * 5e-3):.5f}\n"
        for k in range(401)),
    "load_empty.csv": "",
    "load_acc_huge.csv": "time [s], acceleration [m/s^2]\n0, 0\n0.1, 5000\n0.2, -5000\n"
                         "0.3, 0\n",
    "load_header_only.csv": "time [s], force [N]\n",
    "load_one_sample.csv": "time [s], force [N]\n0, 1\n",
    "load_no_unit.csv": "time [s], force\n0, 0\n1, 1\n",
    "load_nan.csv": "time [s], force [N]\n0, 0\n1, nan\n2, 0\n",
    "load_time_backwards.csv": "time [s], force [N]\n0, 0\n1, 1\n0.5, 0\n",
    "load_displacement.csv": "time [s], displacement [mm]\n0, 0\n1, 1\n",
    "load_two_forces.csv": "time [s], force [N], force2 [N]\n0, 0, 0\n1, 1, 1\n",
    "load_ragged.csv": "time [s], force [N]\n0, 0\n1, 1, 2\n",
    "load_no_time.csv": "force [N], force2 [kN]\n0, 0\n1, 1\n",
    "load_years.csv": "time [year], force [N]\n0, 0\n1, 1\n",
    "modes_undamped.csv": "frequency [Hz], damping ratio [1], damper [kg^-0.5]\n5.56, 0, 0.81\n",
    "modes_overdamped.csv": "frequency [Hz], damping ratio [1], damper [kg^-0.5]\n"
                            "5.56, 1e6, 0.81\n",
    "load_modes_two.csv": "frequency [Hz], damping ratio [1], damper [kg^-0.5]\n"
                          "5.56, 0.0052, 0.81\n46.3, 0.01, -0.9\n",
}

_MAP = ["map", "--frequency", "2Hz:4Hz:2", "--amplitude", "1mm:2mm:2"]
_DEM = ["dem", "--particles", "4", "--cycles", "2", "--skip-cycles", "1"]

#: (id, arguments, expected answer); the ids name the row of the issue's table.
CASES: list[tuple[str, list[str], OK | Error]] = [
    # -- output paths: checked before any computation, one line
    ("out-is-directory-map", [*_MAP, "--out", "{tmp}/dir"], Error("out")),
    ("out-under-file-map", [*_MAP, "--out", "{tmp}/file/x.nc"], Error("out")),
    ("out-missing-dir-map", [*_MAP, "--out", "{tmp}/missing/x.nc"], Error("out")),
    ("out-empty-map", [*_MAP, "--out", ""], Error("out")),
    ("out-blank-map", [*_MAP, "--out", "  "], Error("out")),
    ("out-trailing-slash-map", [*_MAP, "--out", "{tmp}/newdir/"], Error("out")),
    ("out-proc-map", [*_MAP, "--out", "/proc/pdamper-corpus.nc"], Error("out")),
    ("out-fifo-map", [*_MAP, "--out", "{tmp}/fifo"], Error("out")),
    ("out-is-directory-simulate", ["simulate", "--out", "{tmp}/dir"], Error("out")),
    ("out-proc-simulate", ["simulate", "--out", "/proc/pdamper-corpus.nc"], Error("out")),
    ("out-under-file-simulate", ["simulate", "--out", "{tmp}/file/x.nc"], Error("out")),
    ("out-proc-dem", [*_DEM, "--out", "/proc/pdamper-corpus.nc"], Error("out")),
    ("out-under-file-dem", [*_DEM, "--out", "{tmp}/file/x.nc"], Error("out")),
    ("out-is-directory-dem", [*_DEM, "--out", "{tmp}/dir"], Error("out")),
    ("vtk-is-file-dem", [*_DEM, "--vtk", "{tmp}/file"], Error("vtk")),
    ("vtk-missing-parent-dem", [*_DEM, "--vtk", "{tmp}/missing/sub"], Error("vtk")),
    ("vtk-proc-dem", [*_DEM, "--vtk", "/proc/pdamper-corpus"], Error("vtk")),
    ("out-is-file-paper", ["paper", "--no-dem", "--out", "{tmp}/file"], Error("out")),
    ("out-missing-parent-paper", ["paper", "--no-dem", "--out", "{tmp}/missing/sub"],
     Error("out")),
    ("out-empty-paper", ["paper", "--no-dem", "--out", ""], Error("out")),
    ("out-proc-paper", ["paper", "--no-dem", "--out", "/proc/pdamper-corpus"], Error("out")),
    # -- inputs that imply absurd work: refused up front by the resource model
    ("dem-frequency-1e-9Hz", ["dem", "--frequency", "1e-9Hz", "--particles", "4"],
     Error("excitation.frequency")),
    ("dem-sample-rate-1e12Hz", [*_DEM, "--sample-rate", "1e12Hz"], Error("dem.sample_rate")),
    ("dem-sample-rate-1e12Hz-scenario", [*_DEM, "--scenario", "{scenario:sample_rate_huge}"],
     Error("dem.sample_rate")),
    ("dem-cycles-1e20", ["dem", "--particles", "4", "--cycles", "99999999999999999999"],
     Error("dem.cycles")),
    ("radius-1um-analytic", ["analytic", "--scenario", "{scenario:radius_1um}"],
     Error("particles.radius")),
    ("radius-1um-dem", [*_DEM, "--scenario", "{scenario:radius_1um}"],
     Error("particles.radius")),
    ("radius-1um-map", [*_MAP, "--scenario", "{scenario:radius_1um}"],
     Error("particles.radius")),
    ("map-count-1e9", ["map", "--frequency", "2Hz:20Hz:1000000000"], Error("map.frequency")),
    ("map-count-1e20", ["map", "--amplitude", "1mm:2mm:99999999999999999999"],
     Error("map.amplitude")),
    ("map-dem-grid-too-long", ["map", "--model", "dem", "--frequency", "2Hz:20Hz:200",
                               "--amplitude", "1mm:200mm:200"], Error("map.frequency")),
    ("simulate-duration-1e9s", ["simulate", "--duration", "1e9s"], Error("simulation.duration")),
    ("simulate-duration-1e9s-scenario", ["simulate", "--scenario", "{scenario:duration_huge}"],
     Error("simulation.duration")),
    ("simulate-dem-duration-1e5s", ["simulate", "--model", "dem", "--duration", "1e5s"],
     Error("simulation.duration")),
    ("optimize-at-1e8s", ["optimize", "--at", "1e8s"], Error("optimization.at")),
    # -- extreme values: an answer at once, never minutes
    ("frequency-1e300Hz", ["analytic", "--frequency", "1e300Hz"], Error("excitation.frequency")),
    ("frequency-10MHz", ["analytic", "--frequency", "10 MHz"], Error("excitation.frequency")),
    ("amplitude-1e300m", ["analytic", "--amplitude", "1e300m"], Error("excitation.amplitude")),
    ("x0-minus-1e300m", ["simulate", "--initial-displacement=-1e300 m"],
     Error("structure.initial_displacement")),
    ("frequency-1e300Hz-dem", [*_DEM, "--frequency", "1e300Hz"], Error("excitation.frequency")),
    ("map-frequency-1e300Hz", ["map", "--frequency", "2Hz:1e300Hz:3"], Error("map.frequency")),
    # -- quantities need a number; nothing after the unit; well-formed ranges
    ("frequency-unit-only", ["analytic", "--frequency", "Hz"], Error("excitation.frequency")),
    ("amplitude-unit-only", ["analytic", "--amplitude", "mm"], Error("excitation.amplitude")),
    ("frequency-emoji", ["analytic", "--frequency", "10Hz🙂"], Error("excitation.frequency")),
    ("frequency-emoji-scenario", ["analytic", "--scenario", "{scenario:frequency_decorated}"],
     Error("excitation.frequency")),
    ("frequency-expression", ["analytic", "--frequency", "10 Hz * 2"],
     Error("excitation.frequency")),
    ("frequency-rad-per-s", ["analytic", "--frequency", "62.8 rad/s"],
     Error("excitation.frequency")),
    ("ok-frequency-rpm", ["analytic", "--frequency", "600 rpm", "--json"], OK()),
    ("map-range-empty-stop", ["map", "--frequency", "2Hz::5"], Error("map.frequency")),
    ("map-range-four-parts", ["map", "--frequency", "2Hz:4Hz:5:6"], Error("map.frequency")),
    ("map-range-descending", ["map", "--frequency", "20Hz:2Hz:5"], Error("map.frequency")),
    ("map-range-count-one", ["map", "--frequency", "2Hz:20Hz:1"], Error("map.frequency")),
    ("duration-unit-only", ["simulate", "--duration", "s"], Error("simulation.duration")),
    # found by the fuzz suite: a finite number times its unit's factor overflows
    ("amplitude-overflow-by-unit", ["analytic", "--amplitude", "1.797693134862316e+305km"],
     Error("excitation.amplitude")),
    # -- every scenario section validated whichever command reads it
    ("map-section-analytic", ["analytic", "--scenario", "{scenario:map_empty_stop}"],
     Error("map.frequency")),
    ("map-section-no-count-analytic", ["analytic", "--scenario", "{scenario:map_no_count}"],
     Error("map.amplitude")),
    ("map-section-not-text-simulate", ["simulate", "--scenario", "{scenario:map_not_text}"],
     Error("map.frequency")),
    ("material-unknown-key", ["analytic", "--scenario", "{scenario:material_unknown_key}"],
     Error("particles.material.colour")),
    ("material-poisson-half", ["analytic", "--scenario", "{scenario:material_poisson_half}"],
     Error("particles.material.poisson_ratio")),
    ("material-negative-density", ["analytic", "--scenario",
                                   "{scenario:material_negative_density}"],
     Error("container.material.density")),
    ("material-missing-key", ["analytic", "--scenario", "{scenario:material_missing_key}"],
     Error("particles.material.density")),
    ("material-modulus-unitless", ["analytic", "--scenario",
                                   "{scenario:material_modulus_unitless}"],
     Error("particles.material.youngs_modulus")),
    # -- physically meaningless values: refused with the reason
    ("frequency-above-contact", ["analytic", "--frequency", "50kHz", "--amplitude", "0.01mm"],
     Error("excitation.frequency")),
    ("stroke-20m", ["analytic", "--amplitude", "20 m"], Error("excitation.amplitude")),
    ("dem-200Hz-32mm", [*_DEM, "--frequency", "200Hz", "--amplitude", "32mm"],
     Error("excitation.frequency")),
    # -- what must keep working
    ("ok-analytic-mhz", ["analytic", "--frequency", "1e4 mHz", "--json"], OK()),
    ("ok-analytic-per-minute", ["analytic", "--frequency", "600 1/min", "--json"], OK()),
    ("ok-analytic-unicode-minus", ["simulate", "--initial-displacement", "\u221258 mm",
                                   "--duration", "0.5 s", "--json"], OK()),
    ("ok-map-out", [*_MAP, "--out", "{tmp}/m.nc", "--json"], OK()),
    ("ok-map-out-replaces", [*_MAP, "--out", "{tmp}/file", "--json"], OK()),
    ("ok-glass-analytic", ["analytic", "--scenario", "{scenario:glass}", "--json"], OK()),
    ("ok-paper-corner-analytic", ["analytic", "--frequency", "20Hz", "--amplitude", "200mm",
                                  "--json"], OK()),
    ("ok-example-scenario", ["example-scenario"], OK()),
    # -- COR tables in runs, meaningless inputs (block: tables, scales, choices, formats)
    ("dem-cor-table", [*_DEM, "--scenario", "{scenario:cor_table}", "--json"], OK()),
    ("map-dem-cor-table-2x2", ["map", "--model", "dem", "--frequency", "10Hz:15Hz:2",
                               "--amplitude", "5mm:10mm:2", "--workers", "2", "--scenario",
                               "{scenario:cor_table_small_map}", "--json"], OK()),
    ("optimize-material-list-empty", ["optimize", "--vary", "particle-material=,"],
     Error("optimization.vary")),
    ("optimize-material-list-empty-entry", ["optimize", "--vary", "particle-material=S235,,PVC"],
     Error("optimization.vary")),
    ("simulate-measured-in-furlongs", ["simulate", "--measured", "{tmp}/decay_furlong.csv"],
     Error("measured")),
    ("simulate-measured-1mm-release", ["simulate", "--measured", "{tmp}/decay_mm.csv",
                                       "--initial-displacement=-1mm"], Error("measured")),
    ("ok-simulate-measured-mm", ["simulate", "--measured", "{tmp}/decay_mm.csv", "--json"], OK()),
    ("cor-velocity-1e305", ["cor", "--velocity", "1e305m/s"], Error("velocity")),
    ("cor-velocity-range-to-1e305", ["cor", "--velocity", "1m/s:1e305m/s:3"], Error("velocity")),
    ("cor-table-velocity-1e305", ["cor", "--model", "{tmp}/cor_1e305.csv"],
     Error("restitution.particle_wall.file")),
    ("analytic-table-velocity-1e305", ["analytic", "--scenario", "{scenario:cor_table_too_fast}"],
     Error("restitution.particle_wall.file")),
    ("ok-cor-sensitivity-table-by-path", ["cor-sensitivity", "--variants", "{tmp}/cor.csv",
                                          "--points", "10Hz/32mm", "--no-level3", "--cycles", "3",
                                          "--skip-cycles", "1", "--scenario",
                                          "{scenario:four_spheres}", "--json"], OK()),
    ("ok-cor-sensitivity-tables-pp-pw-by-path", [
        "cor-sensitivity", "--variants", "0.6/{tmp}/cor.csv,{tmp}/cor.csv/{tmp}/cor.csv*1.2",
        "--points", "10Hz/32mm", "--no-level3", "--cycles", "3", "--skip-cycles", "1",
        "--scenario", "{scenario:four_spheres}", "--json"], OK()),
    ("simulate-plot-gif", ["simulate", "--plot", "{tmp}/x.gif"], Error("plot")),
    ("simulate-plot-no-suffix", ["simulate", "--plot", "{tmp}/x"], Error("plot")),
    ("optimize-plot-gif", ["optimize", "--plot", "{tmp}/x.gif"], Error("plot")),
    ("cor-plot-gif", ["cor", "--plot", "{tmp}/x.gif"], Error("plot")),
    ("cor-sensitivity-plot-gif", ["cor-sensitivity", "--plot", "{tmp}/x.gif"], Error("plot")),
    ("ok-simulate-plot-jpg", ["simulate", "--duration", "0.5s", "--plot", "{tmp}/x.jpg",
                              "--json"], OK()),


    # -- counts judged by the resource model from their parameters, before anything is
    #    built (a list of 10^9 speeds, design variables of 10^8-10^9 values); --force
    #    lifts the soft limits only
    ("cor-velocity-count-1e9", ["cor", "--velocity", "0.1m/s:1m/s:1000000000"],
     Error("velocity")),
    ("cor-velocity-count-1e9-forced", ["cor", "--velocity", "0.1m/s:1m/s:1000000000",
                                       "--force"], Error("velocity")),
    ("cor-velocity-count-1e7", ["cor", "--velocity", "0.1m/s:1m/s:10000000"],
     Error("velocity")),
    ("optimize-vary-particles-1e9", ["optimize", "--vary", "particles=0:1000000000:1"],
     Error("optimization.vary.particles")),
    ("optimize-vary-particles-1e9-scenario", ["optimize", "--scenario",
                                              "{scenario:vary_particles_huge}"],
     Error("optimization.vary.particles")),
    ("optimize-vary-radius-1e8", ["optimize", "--vary", "radius=1mm:3mm:100000000"],
     Error("optimization.vary.radius")),
    # a scenario's study is checked, not built, by a command that does not run it
    ("ok-analytic-scenario-vary-particles-1e9", ["analytic", "--scenario",
                                                 "{scenario:vary_particles_huge}", "--json"],
     OK()),
    # -- the physics limits of `pdamper dem` on every run: design candidates, cor,
    #    cor-sensitivity
    ("optimize-vary-radius-1nm", ["optimize", "--vary", "radius=1nm:3mm:4"],
     Error("optimization.vary.radius")),
    ("cor-sensitivity-10Hz-100m", ["cor-sensitivity", "--points", "10Hz/100m", "--no-level3"],
     Error("points")),
    ("cor-sensitivity-10Hz-100m-16-spheres", ["cor-sensitivity", "--points", "10Hz/100m",
                                              "--no-level3", "--scenario",
                                              "{scenario:count_16}"], Error("points")),
    ("cor-sensitivity-10Hz-5m", ["cor-sensitivity", "--points", "10Hz/5m", "--no-level3"],
     Error("points")),
    ("cor-velocity-1000mps", ["cor", "--velocity", "1000m/s:2000m/s:2"], Error("velocity")),
    ("cor-velocity-1000mps-sphere-sphere", ["cor", "--velocity", "1000m/s:2000m/s:2",
                                            "--pair", "S235:S235"], Error("velocity")),
    ("ok-optimize-vary-radius", ["optimize", "--vary", "radius=3mm:6mm:3", "--json"], OK()),
    # -- scheduler addresses: judged before anything runs, one line naming the option
    ("scheduler-not-an-address", ["map", "--model", "dem", "--scheduler", "notanaddress",
                                  "--frequency", "2Hz:4Hz:2", "--amplitude", "1mm:2mm:2"],
     Error("scheduler")),
    ("scheduler-empty", ["map", "--model", "dem", "--scheduler", "", "--frequency",
                         "2Hz:4Hz:2", "--amplitude", "1mm:2mm:2"], Error("scheduler")),
    ("scheduler-port-not-a-number", [*_MAP, "--scheduler", "tcp://10.0.0.5:port"],
     Error("scheduler")),
    ("scheduler-unknown-scheme", [*_MAP, "--scheduler", "ftp://10.0.0.5:8786"],
     Error("scheduler")),
    ("scheduler-empty-optimize", ["optimize", "--scheduler", ""],
     Error("optimization.scheduler")),
    ("scheduler-empty-paper", ["paper", "--no-dem", "--scheduler", "", "--out", "{tmp}/p"],
     Error("scheduler")),
    # -- dem --realisations: a whole number >= 1 within the cost limits, random packings only
    ("dem-realisations-0", ["dem", "--realisations", "0"], Error("realisations")),
    ("dem-realisations-negative", ["dem", "--realisations=-3"], Error("realisations")),
    ("dem-realisations-fraction", ["dem", "--realisations", "1.5"], Error("realisations")),
    ("dem-realisations-nan", ["dem", "--realisations", "nan"], Error("realisations")),
    ("dem-realisations-1e12", ["dem", "--packing", "random", "--particles", "16",
                               "--realisations", "1000000000000", "--force"],
     Error("realisations")),
    ("dem-realisations-lattice", ["dem", "--packing", "lattice", "--realisations", "2"],
     Error("realisations")),
    ("dem-realisations-workers-0", ["dem", "--packing", "random", "--particles", "16",
                                    "--realisations", "2", "--workers", "0"], Error("workers")),
    # -- the user's structure: [structure] modes and beam, --modes
    ("modes-missing-file", ["simulate", "--modes", "{tmp}/none.csv"], Error("structure.modes")),
    ("modes-is-directory", ["simulate", "--modes", "{tmp}/dir"], Error("structure.modes")),
    ("modes-no-unit", ["simulate", "--modes", "{tmp}/modes_no_unit.csv"],
     Error("structure.modes")),
    ("modes-nan", ["simulate", "--modes", "{tmp}/modes_nan.csv"], Error("structure.modes")),
    ("modes-negative-frequency", ["optimize", "--modes", "{tmp}/modes_negative_frequency.csv"],
     Error("structure.modes")),
    ("modes-shape-in-metres", ["simulate", "--modes", "{tmp}/modes_shape_in_metres.csv"],
     Error("structure.modes")),
    ("modes-header-only", ["simulate", "--modes", "{tmp}/modes_header_only.csv"],
     Error("structure.modes")),
    ("modes-and-beam", ["simulate", "--scenario", "{scenario:modes_and_beam}"],
     Error("structure")),
    ("modes-and-stiffness", ["simulate", "--scenario", "{scenario:modes_and_stiffness}"],
     Error("structure")),
    ("modes-option-and-beam-scenario", ["simulate", "--modes", "{tmp}/modes_one.csv",
                                        "--scenario", "{scenario:beam_three_modes}"],
     Error("structure")),
    ("beam-damper-beyond-tip", ["simulate", "--scenario", "{scenario:beam_damper_beyond_tip}"],
     Error("structure.beam.damper_position")),
    ("beam-elements-huge", ["simulate", "--scenario", "{scenario:beam_elements_huge}"],
     Error("structure.beam.elements")),
    ("beam-modes-too-many", ["simulate", "--scenario", "{scenario:beam_modes_too_many}"],
     Error("structure.beam.modes")),
    # the DEM runs on the beam's modes (the co-simulation on N modes)
    ("ok-beam-three-modes-dem", ["simulate", "--model", "dem", "--particles", "4",
                                 "--duration", "0.2s", "--scenario",
                                 "{scenario:beam_three_modes}", "--json"], OK()),
    ("ok-simulate-modes-scenario", ["simulate", "--duration", "0.5s", "--scenario",
                                    "{scenario:modes_one}", "--json"], OK()),
    ("paper-beam-three-modes", ["paper", "--no-dem", "--scenario",
                                "{scenario:beam_three_modes}", "--out", "{tmp}/p"],
     Error("structure")),
    ("ok-simulate-beam-three-modes", ["simulate", "--duration", "0.5s", "--scenario",
                                      "{scenario:beam_three_modes}", "--json"], OK()),
    # -- gravity: >= 0 m/s^2 and finite; 0 (orbit) is an input like any other
    ("gravity-negative", ["analytic", "--gravity", "-9.81 m/s^2"], Error("excitation.gravity")),
    ("gravity-infinite-scenario", ["analytic", "--scenario", "{scenario:gravity_inf}"],
     Error("excitation.gravity")),
    ("gravity-not-an-acceleration", ["dem", "--gravity", "9.81 m/s"],
     Error("excitation.gravity")),
    ("ok-analytic-gravity-zero", ["analytic", "--gravity", "0 m/s^2", "--json"], OK()),
    # -- input uncertainty: "value +- sd" (scenario, --uncertain) and --uncertainty N
    ("uncertain-negative-sd", ["analytic", "--scenario",
                               "{scenario:uncertain_friction_negative_sd}"],
     Error("particles.friction")),
    ("uncertain-sd-without-unit", ["analytic", "--scenario",
                                   "{scenario:uncertain_length_no_unit_sd}"],
     Error("container.length")),
    ("uncertain-count", ["analytic", "--scenario", "{scenario:uncertain_count}"],
     Error("particles.count")),
    ("uncertain-cli-no-equals", ["analytic", "--uncertain", "0.1+-0.03", "--uncertainty", "8"],
     Error("uncertain")),
    ("uncertain-cli-no-sd", ["analytic", "--uncertain", "particles.friction=0.1",
                             "--uncertainty", "8"], Error("particles.friction")),
    ("uncertain-cli-two-signs", ["analytic", "--uncertain", "particles.friction=0.1+-0.03+-1"],
     Error("particles.friction")),
    ("uncertain-cli-zero-sd", ["simulate", "--uncertain", "particles.friction=0.1+-0"],
     Error("particles.friction")),
    ("uncertain-cli-unknown-field", ["analytic", "--uncertain", "particles.colour=1+-0.1"],
     Error("particles.colour")),
    ("uncertainty-not-power-of-two", ["analytic", "--scenario", "{scenario:uncertain_friction}",
                                      "--uncertainty", "10"], Error("uncertainty")),
    ("uncertainty-without-uncertain-input", ["analytic", "--uncertainty", "8"],
     Error("uncertainty")),
    ("uncertainty-dem", ["simulate", "--model", "dem", "--scenario",
                         "{scenario:uncertain_friction}", "--uncertainty", "8"],
     Error("uncertainty")),
    ("uncertain-twice", ["analytic", "--particles", "32", "--uncertain",
                         "excitation.frequency=10Hz+-1Hz", "--frequency", "10Hz"],
     Error("excitation.frequency")),
    ("ok-analytic-uncertain-nominal", ["analytic", "--scenario",
                                       "{scenario:uncertain_friction}", "--json"], OK()),
    ("ok-analytic-uncertainty", ["analytic", "--scenario", "{scenario:uncertain_friction}",
                                 "--uncertainty", "4", "--json"], OK()),
    ("optimize-uncertainty-65536", ["optimize", "--uncertain", "particles.friction=0.1+-0.03",
                                    "--uncertainty", "65536"], Error("uncertainty")),
    ("optimize-uncertainty-65536-scenario", ["optimize", "--scenario",
                                             "{scenario:uncertain_friction}",
                                             "--uncertainty", "65536"], Error("uncertainty")),
    # -- pdamper report: its output directory and options, judged before any run
    ("report-out-no-parent", ["report", "--out", "{tmp}/no/such/dir"], Error("out")),
    ("report-out-is-a-file", ["report", "--out", "{tmp}/file"], Error("out")),
    ("report-uncertainty-odd", ["report", "--scenario", "{scenario:uncertain_friction}",
                                "--out", "{tmp}/r", "--uncertainty", "6"], Error("uncertainty")),
    ("report-workers-zero", ["report", "--out", "{tmp}/r", "--workers", "0"], Error("workers")),
    ("report-uncertain-amplitude-after-the-run", ["report", "--scenario",
                                                  "{scenario:uncertain_short_run}", "--out",
                                                  "{tmp}/r"], Error("optimization.at")),
    ("simulate-uncertain-amplitude-after-the-run", [
        "simulate", "--scenario", "{scenario:uncertain_short_run}", "--uncertainty", "4"],
     Error("optimization.at")),
    # -- load histories: --load, --base-acceleration, [load]
    ("load-missing-file", ["simulate", "--load", "{tmp}/none.csv"], Error("load")),
    ("load-is-directory", ["simulate", "--load", "{tmp}/dir"], Error("load")),
    ("load-empty", ["simulate", "--load", "{tmp}/load_empty.csv"], Error("load")),
    ("load-header-only", ["simulate", "--load", "{tmp}/load_header_only.csv"], Error("load")),
    ("load-one-sample", ["simulate", "--load", "{tmp}/load_one_sample.csv"], Error("load")),
    ("load-no-unit", ["simulate", "--load", "{tmp}/load_no_unit.csv"], Error("load")),
    ("load-nan", ["simulate", "--load", "{tmp}/load_nan.csv"], Error("load")),
    ("load-time-backwards", ["simulate", "--load", "{tmp}/load_time_backwards.csv"],
     Error("load")),
    ("load-displacement-column", ["simulate", "--load", "{tmp}/load_displacement.csv"],
     Error("load")),
    ("load-two-force-columns", ["simulate", "--load", "{tmp}/load_two_forces.csv"],
     Error("load")),
    ("load-ragged-row", ["simulate", "--load", "{tmp}/load_ragged.csv"], Error("load")),
    ("load-no-time-column", ["simulate", "--load", "{tmp}/load_no_time.csv"], Error("load")),
    ("base-acceleration-given-a-force", ["simulate", "--base-acceleration",
                                         "{tmp}/load_force.csv"], Error("base_acceleration")),
    ("load-and-base-acceleration", ["simulate", "--load", "{tmp}/load_force.csv",
                                    "--base-acceleration", "{tmp}/load_acc.csv"], Error("load")),
    ("load-scenario-both", ["simulate", "--scenario", "{scenario:load_both}"], Error("load")),
    ("load-tail-negative", ["simulate", "--scenario", "{scenario:load_tail_negative}"],
     Error("load.tail")),
    ("load-tail-not-a-time", ["simulate", "--load", "{tmp}/load_force.csv", "--tail", "1 m"],
     Error("load.tail")),
    ("load-with-measured", ["simulate", "--load", "{tmp}/load_force.csv", "--measured",
                            "{tmp}/decay_mm.csv"], Error("measured")),
    ("load-with-duration", ["simulate", "--load", "{tmp}/load_force.csv", "--duration", "1s"],
     Error("duration")),
    ("ok-load-dem-two-modes", ["simulate", "--model", "dem", "--particles", "4", "--load",
                               "{tmp}/load_force.csv", "--modes", "{tmp}/load_modes_two.csv",
                               "--json"], OK()),
    # base motion on a modes file: no participation factors, in the DEM as in the others
    ("base-acceleration-dem-two-modes-file", ["simulate", "--model", "dem", "--particles",
                                              "4", "--base-acceleration",
                                              "{tmp}/load_acc.csv", "--modes",
                                              "{tmp}/load_modes_two.csv"],
     Error("base_acceleration")),
    ("base-acceleration-two-modes-file", ["simulate", "--base-acceleration",
                                          "{tmp}/load_acc.csv", "--modes",
                                          "{tmp}/load_modes_two.csv"],
     Error("base_acceleration")),
    ("ok-simulate-base-acceleration-beam-three-modes", ["simulate", "--base-acceleration",
                                                        "{tmp}/load_acc.csv", "--scenario",
                                                        "{scenario:beam_three_modes}",
                                                        "--json"], OK()),
    ("load-record-of-a-year", ["simulate", "--load", "{tmp}/load_years.csv"],
     Error("simulation.sample_rate")),
    ("load-tail-a-billion-seconds", ["simulate", "--load", "{tmp}/load_force.csv", "--tail",
                                     "1e9 s"], Error("simulation.sample_rate")),
    ("load-tail-without-load", ["simulate", "--tail", "1s"], Error("load.tail")),
    ("ok-load-compare-with-dem-two-modes", ["simulate", "--compare", "analytic,dem",
                                            "--particles", "4", "--load",
                                            "{tmp}/load_force.csv", "--modes",
                                            "{tmp}/load_modes_two.csv", "--json"], OK()),
    ("ok-simulate-load", ["simulate", "--load", "{tmp}/load_force.csv", "--json"], OK()),
    ("ok-simulate-load-scenario", ["simulate", "--scenario", "{scenario:load_force}",
                                   "--json"], OK()),
    ("ok-simulate-base-acceleration-one-mode", ["simulate", "--base-acceleration",
                                                "{tmp}/load_acc.csv", "--modes",
                                                "{tmp}/modes_one.csv", "--json"], OK()),
    ("ok-simulate-load-three-modes", ["simulate", "--load", "{tmp}/load_force.csv",
                                      "--scenario", "{scenario:beam_three_modes}", "--json"],
     OK()),
    ("optimize-peak-without-load", ["optimize", "--objective", "peak"],
     Error("optimization.objective")),
    ("optimize-load-free-decay-objective", ["optimize", "--load", "{tmp}/load_force.csv"],
     Error("optimization.objective")),
    ("optimize-peak-load-nan", ["optimize", "--objective", "peak", "--load",
                                "{tmp}/load_nan.csv"], Error("load")),
    ("optimize-peak-dem", ["optimize", "--model", "dem", "--objective", "peak", "--load",
                           "{tmp}/load_force.csv", "--vary", "particles=16:32:16"],
     Error("simulation.model")),
    ("ok-optimize-peak", ["optimize", "--objective", "peak", "--load", "{tmp}/load_force.csv",
                          "--vary", "particles=0:32:32", "--json"], OK()),
    ("ok-optimize-rms-base-acceleration", ["optimize", "--objective", "rms",
                                           "--base-acceleration", "{tmp}/load_acc.csv",
                                           "--vary", "particles=0:32:32", "--json"], OK()),
    # -- realisations of maps, Level III, design studies and the case study: a whole number
    # >= 1 within the cost limits, only for a model with a random packing
    ("map-realisations-analytic", ["map", "--realisations", "2"], Error("realisations")),
    ("map-realisations-nan", ["map", "--model", "dem", "--realisations", "nan"],
     Error("realisations")),
    ("map-realisations-1e12", ["map", "--model", "dem", "--realisations", "1000000000000",
                               "--force", "--scenario", "{scenario:dem_random}"],
     Error("realisations")),
    ("simulate-realisations-lattice", ["simulate", "--model", "dem", "--realisations", "2"],
     Error("realisations")),
    ("simulate-realisations-analytic", ["simulate", "--realisations", "3"],
     Error("realisations")),
    ("simulate-realisations-1e12", ["simulate", "--model", "dem", "--realisations",
                                    "1000000000000", "--force", "--scenario",
                                    "{scenario:dem_random}"], Error("realisations")),
    ("simulate-realisations-at-past-the-end", ["simulate", "--model", "dem", "--duration",
                                               "0.5s", "--at", "1s", "--realisations", "2",
                                               "--scenario", "{scenario:dem_random}"],
     Error("optimization.at")),
    ("optimize-realisations-inf", ["optimize", "--model", "dem", "--realisations", "inf"],
     Error("realisations")),
    ("optimize-realisations-1e12", ["optimize", "--model", "dem", "--realisations",
                                    "1000000000000", "--force", "--scenario",
                                    "{scenario:dem_random}"], Error("realisations")),
    ("paper-realisations-0", ["paper", "--realisations", "0", "--out", "{tmp}/p"],
     Error("realisations")),
    ("simulate-realisations-with-load", ["simulate", "--model", "dem", "--realisations", "2",
                                         "--scenario", "{scenario:load_force}"],
     Error("realisations")),
    # -- forced response (frf): the load, the frequency grid, the sweep, the structure
    ("frf-force-negative", ["frf", "--force", "-2N"], Error("force")),
    ("frf-force-zero", ["frf", "--force", "0N"], Error("force")),
    ("frf-force-a-length", ["frf", "--force", "2mm"], Error("force")),
    ("frf-force-infinite", ["frf", "--force", "inf N"], Error("force")),
    ("frf-force-and-base", ["frf", "--force", "2N", "--base", "1mm"], Error("base")),
    ("frf-base-a-duration", ["frf", "--base", "3 s"], Error("base")),
    ("frf-base-negative", ["frf", "--base", "-1mm"], Error("base")),
    ("frf-base-on-three-modes", ["frf", "--base", "0.3g", "--frequency", "5Hz",
                                 "--scenario", "{scenario:beam_three_modes}"], Error("base")),
    ("frf-frequency-zero", ["frf", "--frequency", "0Hz:9Hz:3"], Error("frequency")),
    ("frf-frequency-a-length", ["frf", "--frequency", "3mm:9mm:3"], Error("frequency")),
    ("frf-frequency-no-count", ["frf", "--frequency", "3Hz:9Hz"], Error("frequency")),
    ("frf-frequency-negative-one", ["frf", "--frequency", "-5Hz"], Error("frequency")),
    ("frf-frequency-count-1e9", ["frf", "--frequency", "3Hz:9Hz:1000000000"],
     Error("frequency")),
    ("frf-force-huge", ["frf", "--force", "1e6N", "--frequency", "5Hz"], Error("force")),
    ("frf-base-huge", ["frf", "--base", "100m", "--frequency", "5Hz"], Error("base")),
    ("frf-sweep-sideways", ["frf", "--sweep", "sideways"], Error("sweep")),
    ("frf-max-cycles-zero", ["frf", "--max-cycles", "0"], Error("max_cycles")),
    # the DEM's stepped sine runs on the beam's modes
    ("ok-frf-dem-three-modes", ["frf", "--frequency", "5Hz", "--particles", "4",
                                "--max-cycles", "6", "--sweep", "up", "--scenario",
                                "{scenario:frf_dem_three_modes}", "--json"], OK()),
    ("frf-out-directory", ["frf", "--frequency", "5Hz", "--out", "{tmp}/dir"], Error("out")),
    ("frf-plot-no-suffix", ["frf", "--frequency", "5Hz", "--plot", "{tmp}/figure"],
     Error("plot")),
    ("frf-modes-nan", ["frf", "--frequency", "5Hz", "--modes", "{tmp}/modes_nan.csv"],
     Error("structure.modes")),
    ("ok-frf-base-acceleration", ["frf", "--base", "0.05g", "--frequency", "4Hz:7Hz:4",
                                  "--json"], OK()),
    ("ok-frf-modes-one", ["frf", "--frequency", "5Hz:6Hz:3", "--modes",
                          "{tmp}/modes_one.csv", "--json"], OK()),
    ("ok-frf-beam-three-modes", ["frf", "--frequency", "5Hz:7Hz:3", "--scenario",
                                 "{scenario:beam_three_modes}", "--json"], OK()),
    ("optimize-frf-load-a-duration", ["optimize", "--objective", "peak-frf", "--frf-load",
                                      "3 s"], Error("optimization.frf_load")),
    ("optimize-frf-band-zero", ["optimize", "--objective", "rms-frf", "--band", "0Hz:9Hz:3"],
     Error("optimization.band")),
    ("optimize-objective-unknown-frf", ["optimize", "--objective", "peak-frff"],
     Error("optimization.objective")),
    # -- COR fit uncertainty through the DEM (--uncertain restitution.PAIR=fit)
    ("dem-fit-uncertainty-table-without-fit", [
        "dem", "--scenario", "{scenario:cor_table_small_map}", "--uncertain",
        "restitution.particle_wall=fit", "--uncertainty", "4"],
     Error("restitution.particle_wall")),
    ("dem-fit-uncertainty-no-curve", ["dem", "--uncertain", "restitution.particle_wall=fit",
                                      "--uncertainty", "4"], Error("restitution.particle_wall")),
    ("dem-fit-uncertainty-unknown-pair", ["dem", "--uncertain", "restitution.particle_sky=fit",
                                          "--uncertainty", "4"], Error("uncertain")),
    ("dem-fit-uncertainty-not-a-curve", ["dem", "--uncertain", "particles.friction=fit",
                                         "--uncertainty", "4"], Error("particles.friction")),
    ("dem-fit-uncertainty-twice", [
        "dem", "--scenario", "{scenario:cor_fit_small}", "--uncertain",
        "restitution.particle_wall=fit", "--uncertain", "restitution.particle_wall=FIT",
        "--uncertainty", "4"], Error("restitution.particle_wall")),
    ("analytic-fit-uncertainty", ["analytic", "--scenario", "{scenario:cor_fit_small}",
                                  "--uncertain", "restitution.particle_wall=fit",
                                  "--uncertainty", "4"], Error("restitution.particle_wall")),
    ("dem-uncertainty-with-out", [
        "dem", "--scenario", "{scenario:cor_fit_small}", "--uncertain",
        "restitution.particle_wall=fit", "--uncertainty", "4", "--out", "{tmp}/x.nc"],
     Error("uncertainty")),
    ("dem-uncertainty-odd", ["dem", "--scenario", "{scenario:cor_fit_small}", "--uncertain",
                             "restitution.particle_wall=fit", "--uncertainty", "6"],
     Error("uncertainty")),
    ("dem-uncertainty-without-input", ["dem", "--scenario", "{scenario:cor_fit_small}",
                                       "--uncertainty", "4"], Error("uncertainty")),
    ("dem-uncertainty-65536-forced", ["dem", "--uncertain", "particles.friction=0.1+-0.03",
                                      "--uncertainty", "65536", "--force"],
     Error("uncertainty")),
    ("ok-dem-fit-uncertainty", ["dem", "--scenario", "{scenario:cor_fit_small}",
                                "--uncertain", "restitution.particle_wall=fit",
                                "--uncertainty", "4", "--serial", "--json"], OK()),
    ("ok-dem-fit-nominal", ["dem", "--scenario", "{scenario:cor_fit_small}", "--uncertain",
                            "restitution.particle_wall=fit", "--json"], OK()),
    # -- the DEM under a load history
    ("ok-simulate-load-dem", ["simulate", "--model", "dem", "--particles", "4", "--load",
                              "{tmp}/load_force.csv", "--json"], OK()),
    ("load-dem-beyond-hertz", ["simulate", "--model", "dem", "--base-acceleration",
                               "{tmp}/load_acc_huge.csv"], Error("base_acceleration")),
]

# -- degenerate values reaching the numerics: a declared range, or finite numbers
CASES += [
    ("frf-force-1e-200N", ["frf", "--force", "1e-200N", "--frequency", "5Hz"], Error("force")),
    ("frf-force-1e-320N", ["frf", "--force", "1e-320N", "--frequency", "5Hz"], Error("force")),
    ("frf-base-1e-300mm", ["frf", "--base", "1e-300mm", "--frequency", "5Hz"], Error("base")),
    ("frf-base-1e-300g", ["frf", "--base", "1e-300g", "--frequency", "5Hz"], Error("base")),
    ("frf-undamped-structure", ["frf", "--frequency", "5Hz", "--scenario",
                                "{scenario:undamped}"], Error("structure.damping")),
    ("frf-overdamped-structure", ["frf", "--frequency", "5Hz", "--scenario",
                                  "{scenario:overdamped}"], Error("structure.damping")),
    ("simulate-overdamped-structure", ["simulate", "--scenario", "{scenario:overdamped}"],
     Error("structure.damping")),
    ("frf-modes-undamped", ["frf", "--frequency", "5.56Hz", "--modes",
                            "{tmp}/modes_undamped.csv"], Error("structure.damping_ratios")),
    ("frf-modes-overdamped", ["frf", "--frequency", "5Hz:6Hz:3", "--modes",
                              "{tmp}/modes_overdamped.csv"], Error("structure.modes")),
    ("simulate-modes-overdamped", ["simulate", "--modes", "{tmp}/modes_overdamped.csv"],
     Error("structure.modes")),
    ("optimize-frf-load-1e-200N", ["optimize", "--objective", "peak-frf", "--frf-load",
                                   "1e-200N"], Error("optimization.frf_load")),
    ("optimize-frf-load-1e-200N-scenario", ["optimize", "--scenario",
                                            "{scenario:frf_load_tiny}"],
     Error("optimization.frf_load")),
    ("optimize-peak-frf-undamped", ["optimize", "--objective", "peak-frf", "--scenario",
                                    "{scenario:undamped}"], Error("structure.damping")),
    ("optimize-peak-frf-undamped-scenario", ["optimize", "--scenario",
                                             "{scenario:undamped_peak_frf}"],
     Error("structure.damping")),
    ("optimize-peak-frf-modes-undamped", ["optimize", "--objective", "peak-frf", "--modes",
                                          "{tmp}/modes_undamped.csv"],
     Error("structure.damping_ratios")),
    ("analytic-uncertainty-seed-negative", ["analytic", "--scenario",
                                            "{scenario:uncertain_friction}", "--uncertainty",
                                            "4", "--uncertainty-seed", "-1"],
     Error("--uncertainty-seed")),
    ("analytic-uncertainty-fraction", ["analytic", "--scenario", "{scenario:uncertain_friction}",
                                       "--uncertainty", "4.0"], Error("--uncertainty")),
    ("report-uncertainty-fraction", ["report", "--scenario", "{scenario:uncertain_friction}",
                                     "--out", "{tmp}/r", "--uncertainty", "4.0"],
     Error("--uncertainty")),
    ("ok-frf-force-1uN", ["frf", "--force", "1uN", "--frequency", "5Hz:6Hz:3", "--json"], OK()),
    ("ok-frf-base-1nm", ["frf", "--base", "1nm", "--frequency", "5Hz:6Hz:3", "--json"], OK()),
    ("ok-simulate-undamped", ["simulate", "--scenario", "{scenario:undamped}", "--duration",
                              "0.5s", "--json"], OK()),
    ("ok-report-undamped", ["report", "--scenario", "{scenario:undamped}", "--out", "{tmp}/r",
                            "--json"], OK()),
    ("ok-report-objective-rms-load", ["report", "--scenario", "{scenario:study_rms_load}",
                                      "--out", "{tmp}/r", "--json"], OK()),
    ("ok-report-objective-peak-frf", ["report", "--scenario", "{scenario:study_peak_frf}",
                                      "--out", "{tmp}/r", "--json"], OK()),
    ("ok-optimize-plot-peak-frf", ["optimize", "--scenario", "{scenario:study_peak_frf}",
                                   "--plot", "{tmp}/landscape.png", "--json"], OK()),
    ("ok-optimize-plot-rms-load", ["optimize", "--scenario", "{scenario:study_rms_load}",
                                   "--plot", "{tmp}/landscape.png", "--json"], OK()),
    ("ok-analytic-uncertainty-seed", ["analytic", "--scenario", "{scenario:uncertain_friction}",
                                      "--uncertainty", "4", "--uncertainty-seed", "7",
                                      "--json"], OK()),
]

#: Address space [bytes] a case may map beyond what the test process holds
#: (``answers.memory_headroom``): where a regression would build what the input implies
#: (gigabytes), it fails at once instead of taking the machine's memory.
HEADROOM: dict[str, float] = {
    name: 2**30 for name in (
        "cor-velocity-count-1e9", "cor-velocity-count-1e9-forced", "cor-velocity-count-1e7",
        "optimize-vary-particles-1e9", "optimize-vary-particles-1e9-scenario",
        "optimize-vary-radius-1e8", "ok-analytic-scenario-vary-particles-1e9")}
# forced response (frf): a frequency count judged before the grid is built
HEADROOM["frf-frequency-count-1e9"] = 2**30

# -- zero gravity: the forced response answers where the analytical model does
SCENARIOS["gravity_zero"] = '[excitation]\ngravity = "0 m/s^2"\n'
CASES += [
    ("ok-frf-gravity-zero", ["frf", "--scenario", "{scenario:gravity_zero}", "--frequency",
                             "5.35Hz", "--json"], OK()),
    ("ok-report-gravity-zero", ["report", "--scenario", "{scenario:gravity_zero}", "--out",
                                "{tmp}/r", "--json"], OK()),
]

# -- a beam's constants partly given (the rest would silently be the paper beam's)
SCENARIOS["beam_modulus_only"] = '[structure]\nbeam = { youngs_modulus = "70 GPa" }\n'
SCENARIOS["beam_no_density"] = ('[structure]\nbeam = { youngs_modulus = "70 GPa", '
                                'poisson_ratio = 0.33 }\n')
CASES += [
    ("beam-modulus-only-simulate", ["simulate", "--scenario", "{scenario:beam_modulus_only}"],
     Error("structure.beam.poisson_ratio")),
    ("beam-modulus-only-frf", ["frf", "--scenario", "{scenario:beam_modulus_only}",
                               "--frequency", "5Hz"], Error("structure.beam.poisson_ratio")),
    ("beam-no-density-simulate", ["simulate", "--scenario", "{scenario:beam_no_density}"],
     Error("structure.beam.density")),
]

# -- costs of the forced response judged before the work: frequencies x sweeps x cycles per
# step x modes x the fidelity's per-cycle cost (refusals are instant; --allow-cost lifts
# the usual limits as every other command's --force)
_MODES_HEAD = "frequency [Hz], damping ratio [1], damper [kg^-0.5]\n"
FILES.update({
    "modes_50.csv": _MODES_HEAD + "".join(f"{5.56 * k:.3f}, 0.01, 0.5\n" for k in range(1, 51)),
    "modes_3000.csv": _MODES_HEAD + "".join(f"{5.56 * k:.3f}, 0.01, 0.5\n"
                                            for k in range(1, 3001)),
})
SCENARIOS.update({
    "modes_50": '[structure]\nmodes = "modes_50.csv"\n',
    "modes_3000": '[structure]\nmodes = "modes_3000.csv"\n',
    "frf_dem": '[simulation]\nmodel = "dem"\n',
})
CASES += [
    ("frf-frequency-count-20000", ["frf", "--frequency", "4Hz:7Hz:20000"], Error("frequency")),
    ("frf-frequency-count-100000", ["frf", "--frequency", "4Hz:7Hz:100000"],
     Error("frequency")),
    ("frf-max-cycles-1e8", ["frf", "--frequency", "5Hz", "--max-cycles", "100000000"],
     Error("max_cycles")),
    ("ok-frf-max-cycles-1e8-allow-cost", ["frf", "--frequency", "5Hz", "--max-cycles",
                                          "100000000", "--allow-cost", "--json"], OK()),
    ("frf-modes-50-grid", ["frf", "--modes", "{tmp}/modes_50.csv", "--frequency",
                           "3Hz:9Hz:1000"], Error("structure.modes")),
    ("frf-modes-50-grid-scenario", ["frf", "--scenario", "{scenario:modes_50}", "--frequency",
                                    "3Hz:9Hz:1000"], Error("structure.modes")),
    ("frf-modes-3000-one-frequency", ["frf", "--modes", "{tmp}/modes_3000.csv", "--frequency",
                                      "5Hz"], Error("structure.modes")),
    ("frf-modes-3000-one-frequency-scenario", ["frf", "--scenario", "{scenario:modes_3000}",
                                               "--frequency", "5Hz"], Error("structure.modes")),
    ("frf-dem-1mHz", ["frf", "--model", "dem", "--frequency", "0.001Hz"], Error("frequency")),
    ("frf-dem-1mHz-scenario", ["frf", "--scenario", "{scenario:frf_dem}", "--frequency",
                               "0.001Hz"], Error("frequency")),
    ("frf-dem-1mHz-allowed-beyond-any-run", ["frf", "--model", "dem", "--frequency",
                                             "0.0001Hz", "--allow-cost"], Error("frequency")),
    ("ok-frf-modes-50-few-cycles", ["frf", "--modes", "{tmp}/modes_50.csv", "--frequency",
                                    "5Hz", "--max-cycles", "5", "--json"], OK()),
]
HEADROOM.update({name: 2**30 for name in (
    "frf-frequency-count-20000", "frf-frequency-count-100000", "frf-modes-50-grid",
    "frf-modes-50-grid-scenario", "frf-modes-3000-one-frequency",
    "frf-modes-3000-one-frequency-scenario", "frf-dem-1mHz", "frf-dem-1mHz-scenario",
    "frf-dem-1mHz-allowed-beyond-any-run")})

# -- the forced-response objectives: the band judged before it is built, the load against
# the physics limits at the steady stroke it drives the bare structure to
SCENARIOS.update({
    "study_frf_load_huge": '[optimization]\nobjective = "peak-frf"\nfrf_load = "1e6 N"\n',
    "study_band_huge": '[optimization]\nobjective = "peak-frf"\nband = "4Hz:7Hz:1000000"\n',
})
CASES += [
    ("optimize-frf-load-1e6N", ["optimize", "--objective", "peak-frf", "--frf-load", "1e6N"],
     Error("optimization.frf_load")),
    ("optimize-frf-load-1e6N-scenario", ["optimize", "--scenario",
                                         "{scenario:study_frf_load_huge}"],
     Error("optimization.frf_load")),
    ("optimize-band-count-100000", ["optimize", "--objective", "peak-frf", "--band",
                                    "4Hz:7Hz:100000"], Error("optimization.band")),
    ("optimize-band-count-1e6", ["optimize", "--objective", "peak-frf", "--band",
                                 "4Hz:7Hz:1000000"], Error("optimization.band")),
    ("optimize-band-count-1e6-scenario", ["optimize", "--scenario",
                                          "{scenario:study_band_huge}"],
     Error("optimization.band")),
]
HEADROOM.update({name: 2**30 for name in (
    "optimize-band-count-100000", "optimize-band-count-1e6", "optimize-band-count-1e6-scenario")})

def _modes_file(n: int) -> str:
    """A modes file of ``n`` modes from 5 Hz up, 1 % damping, shapes falling as 1/k."""
    rows = [f"{5.0 * (1 + 0.5 * k):.4g}, 0.01, {0.8 / (k + 1):.4g}" for k in range(n)]
    return "frequency [Hz], damping ratio [1], damper [kg^-0.5]\n" + "\n".join(rows) + "\n"


FILES.update({"modes_50.csv": _modes_file(50)})

# -- the modal free vibration costed from its mode count (the state's eigen-decomposition and
# the scan for each minimum, ~(2N)^3 and ~(2N)^2 per sample): refused before any matrix is
# built; uncertainty propagations judged at a sample's measured cost, one after another
CASES += [
    ("simulate-modes-3000", ["simulate", "--modes", "{tmp}/modes_3000.csv"],
     Error("structure.modes")),
    ("simulate-modes-3000-scenario", ["simulate", "--scenario", "{scenario:modes_3000}"],
     Error("structure.modes")),
    ("ok-simulate-modes-50", ["simulate", "--modes", "{tmp}/modes_50.csv", "--duration",
                              "0.2s", "--json"], OK()),
    ("report-uncertainty-65536", ["report", "--scenario", "{scenario:uncertain_friction}",
                                  "--out", "{tmp}/r", "--uncertainty", "65536"],
     Error("uncertainty")),
    ("simulate-uncertainty-65536", ["simulate", "--scenario", "{scenario:uncertain_friction}",
                                    "--uncertainty", "65536"], Error("uncertainty")),
]
HEADROOM.update({name: 2**30 for name in (
    "simulate-modes-3000", "simulate-modes-3000-scenario",
    "report-uncertainty-65536", "simulate-uncertainty-65536")})

# -- a design study on N modes: every candidate's modal free vibration costed from the mode
# count (the same cost as one free vibration, times the candidates), refused before any run
CASES += [
    ("optimize-modes-3000", ["optimize", "--modes", "{tmp}/modes_3000.csv"],
     Error("structure.modes")),
    ("optimize-modes-3000-scenario", ["optimize", "--scenario", "{scenario:modes_3000}"],
     Error("structure.modes")),
]
HEADROOM.update({name: 2**30 for name in ("optimize-modes-3000",
                                          "optimize-modes-3000-scenario")})

# -- 1 000 modes: from 5 Hz to 2.5 kHz the free vibration runs within the limits (measured:
# docs/performance.md); up to 5.6 kHz the scan of the fastest mode needs more memory than
# the limit, judged from the count and the frequencies before any matrix is built
FILES["modes_1000_fast.csv"] = _MODES_HEAD + "".join(f"{5.56 * k:.3f}, 0.01, 0.5\n"
                                                     for k in range(1, 1001))
SCENARIOS["modes_1000_fast"] = '[structure]\nmodes = "modes_1000_fast.csv"\n'
CASES += [
    ("simulate-modes-1000-fast", ["simulate", "--modes", "{tmp}/modes_1000_fast.csv"],
     Error("structure.modes")),
    ("simulate-modes-1000-fast-scenario", ["simulate", "--scenario",
                                           "{scenario:modes_1000_fast}"],
     Error("structure.modes")),
]
HEADROOM.update({name: 2**30 for name in ("simulate-modes-1000-fast",
                                          "simulate-modes-1000-fast-scenario")})

# -- one judge of every load against the physics limits (runs.resources.check_load): load
# histories by the bare structure's response to their largest spectral line, before any run
FILES["load_force_huge.csv"] = "time [s], force [N]\n" + "".join(
    f"{k * 5e-3:.3f}, {1e6 * __import__('math').sin(2 * __import__('math').pi * 5 * k * 5e-3):.1f}\n"
    for k in range(401))
SCENARIOS.update({
    "load_force_huge": '[load]\nforce = "load_force_huge.csv"\n',
    "load_acc_huge": '[load]\nbase_acceleration = "load_acc_huge.csv"\n',
})
CASES += [
    ("simulate-load-force-huge", ["simulate", "--load", "{tmp}/load_force_huge.csv"],
     Error("load")),
    ("simulate-load-force-huge-scenario", ["simulate", "--scenario",
                                           "{scenario:load_force_huge}"], Error("load")),
    ("optimize-peak-load-force-huge", ["optimize", "--objective", "peak", "--load",
                                       "{tmp}/load_force_huge.csv", "--vary",
                                       "particles=0:32:32"], Error("load")),
    ("optimize-rms-base-acceleration-huge", ["optimize", "--objective", "rms",
                                             "--base-acceleration", "{tmp}/load_acc_huge.csv",
                                             "--vary", "particles=0:32:32"],
     Error("base_acceleration")),
    ("simulate-base-acceleration-huge", ["simulate", "--base-acceleration",
                                         "{tmp}/load_acc_huge.csv"], Error("base_acceleration")),
    ("simulate-base-acceleration-huge-scenario", ["simulate", "--scenario",
                                                  "{scenario:load_acc_huge}"],
     Error("base_acceleration")),
]

# -- a harmonic load for the forced-response objectives on N modes: judged before the study
# (base motion on N modes is refused, a force by the bare stroke it drives), never as every
# design failing
FILES["modes_frame.csv"] = ("frequency [Hz], damping ratio [%], damper [kg^-0.5], "
                            "load [kg^-0.5], observation [kg^-0.5]\n"
                            "12.0, 1.0, 0.2582, 0.1500, 0.2582\n"
                            "31.0, 0.8, -0.3162, 0.2400, -0.3162\n")
SCENARIOS["frame_base_peak_frf"] = ('[structure]\nmodes = "modes_frame.csv"\n'
                                    '[optimization]\nobjective = "peak-frf"\n'
                                    'frf_load = "50 mm"\nvary = ["particles=0:32:32"]\n'
                                    'band = "10Hz:14Hz:3"\n')
CASES += [
    ("optimize-peak-frf-base-on-modes", ["optimize", "--objective", "peak-frf", "--modes",
                                         "{tmp}/modes_frame.csv", "--frf-load", "50mm",
                                         "--vary", "particles=0:32:32", "--band",
                                         "10Hz:14Hz:3"], Error("optimization.frf_load")),
    ("optimize-peak-frf-base-on-modes-scenario", ["optimize", "--scenario",
                                                  "{scenario:frame_base_peak_frf}"],
     Error("optimization.frf_load")),
    ("optimize-peak-frf-huge-force-on-modes", ["optimize", "--objective", "peak-frf",
                                               "--modes", "{tmp}/modes_frame.csv",
                                               "--frf-load", "1e7N", "--vary",
                                               "particles=0:32:32", "--band", "10Hz:14Hz:3"],
     Error("optimization.frf_load")),
]
# -- the forced response's harmonic load judged by the same check before any frequency
CASES += [
    ("frf-base-on-modes", ["frf", "--modes", "{tmp}/modes_frame.csv", "--base", "1mm",
                           "--frequency", "10Hz:12Hz:3"], Error("base")),
    ("frf-unbalance-huge-on-modes", ["frf", "--modes", "{tmp}/modes_frame.csv",
                                     "--unbalance", "1e6kg*mm"], Error("unbalance")),
    ("frf-force-huge-on-modes", ["frf", "--modes", "{tmp}/modes_frame.csv", "--force",
                                 "1e7N", "--frequency", "10Hz:12Hz:3"], Error("force")),
]
