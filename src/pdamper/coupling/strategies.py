"""The rows of the coupling table (:data:`pdamper.coupling.registry.COUPLINGS`).

=================  =========================================  ==========================
coupling           release / load history / harmonic sweep     structures
=================  =========================================  ==========================
``pseudo_force``   Sect. 4.1 models 2 and 3: the damper as      1-DOF and N modes, each
                   ``-(m_eff a_c + d v_c)`` updated per cycle   experiment; harmonic
                                                                balance too
``co_simulation``  model 1: the DEM integrated with the         1-DOF (Eq. 23) and N
                   structure                                    modes, each experiment
``plastic_bed``    the analytical bed as a plastic block,       1-DOF and N modes, each
                   event by event                               experiment
=================  =========================================  ==========================

A strategy is a subclass of :class:`~pdamper.coupling.registry.Coupling` whose methods are
the implementations in their modules (:mod:`~pdamper.coupling.pseudo_force`,
:mod:`~pdamper.coupling.modal`, :mod:`~pdamper.coupling.loads`,
:mod:`~pdamper.coupling.cosimulation`, :mod:`~pdamper.coupling.plastic`,
:mod:`~pdamper.coupling.frf`) and whose ``answers`` say which experiments and structures it
runs. A new form of an existing coupling is one method and one structure kind in its row
(e.g. the DEM on N modes: ``modal_free_vibration`` and :data:`MODES` under ``release``); a
new coupling is one class in :func:`register`'s call.
"""

from __future__ import annotations

from pdamper.coupling.registry import (
    HARMONIC_SWEEP,
    LOAD_HISTORY,
    MODES,
    RELEASE,
    SINGLE_DOF,
    Coupling,
    register,
    structure_kind,
)

_BOTH = (SINGLE_DOF, MODES)


class PseudoForce(Coupling):
    """The pseudo force of the Level II models (analytic, fields; Sect. 4.1 models 2, 3)."""

    name = "pseudo_force"
    answers = {RELEASE: _BOTH, LOAD_HISTORY: _BOTH, HARMONIC_SWEEP: _BOTH}
    harmonic_balance = True

    def free_vibration(self, model, structure, duration, initial_displacement,
                       sample_rate=2000.0):
        from pdamper.coupling.pseudo_force import simulate_pseudo_force

        return simulate_pseudo_force(model, structure, duration, initial_displacement,
                                     sample_rate)

    def modal_free_vibration(self, model, structure, duration, initial_displacement,
                             sample_rate=2000.0):
        from pdamper.coupling.modal import simulate_modal_pseudo_force

        return simulate_modal_pseudo_force(model, structure, duration, initial_displacement,
                                           sample_rate)

    def load(self, model, structure, load, sample_rate=2000.0, tail=0.0):
        from pdamper.coupling.loads import simulate_load

        return simulate_load(model, structure, load, sample_rate, tail)

    def stepped_sine(self, model, structure, load, frequency, direction, **options):
        from pdamper.coupling.frf import stepped_sine_pseudo_force

        return stepped_sine_pseudo_force(model, structure, load, frequency, direction,
                                         **options)


class CoSimulation(Coupling):
    """The DEM integrated together with the structure (the paper's model 1)."""

    name = "co_simulation"
    answers = {RELEASE: _BOTH, LOAD_HISTORY: _BOTH, HARMONIC_SWEEP: _BOTH}
    integrates_particles = True

    def structure_for(self, experiment, model, structure):
        # one mode with the damper at the output and release point runs as its 1-DOF
        # (Eq. 23, the kernels' scalar structure), N modes as modes
        from pdamper.coupling.cosimulation import single_dof

        return single_dof(super().structure_for(experiment, model, structure))

    def free_vibration(self, model, structure, duration, initial_displacement,
                       sample_rate=2000.0):
        from pdamper.coupling.cosimulation import co_simulate

        return co_simulate(model, structure, duration, initial_displacement, sample_rate)

    def modal_free_vibration(self, model, structure, duration, initial_displacement,
                             sample_rate=2000.0):
        from pdamper.coupling.cosimulation import co_simulate, co_simulate_modes, single_dof

        structure = single_dof(structure)
        run = co_simulate_modes if structure_kind(structure) == MODES else co_simulate
        return run(model, structure, duration, initial_displacement, sample_rate)

    def load(self, model, structure, load, sample_rate=2000.0, tail=0.0):
        from pdamper.coupling.cosimulation import co_simulate_load

        return co_simulate_load(model, structure, load, sample_rate, tail)

    def load_cost(self, model, structure, load, sample_rate, tail):
        from pdamper.coupling.cosimulation import load_cost

        return load_cost(model, structure, load, sample_rate, tail)[0]

    def check_load_structure(self, model, structure) -> None:
        from pdamper.coupling.cosimulation import single_dof

        single_dof(structure)

    def stepped_sine(self, model, structure, load, frequency, direction, **options):
        # the stepped sine checks the structure itself (one mode with the damper, the load
        # and the output at one point)
        from pdamper.coupling.frf import stepped_sine_co_simulation

        return stepped_sine_co_simulation(model, structure, load, frequency, direction,
                                          **options)


class PlasticBed(Coupling):
    """The analytical bed as a perfectly plastic block on the structure, event by event
    (:class:`~pdamper.coupling.plastic.PlasticBedCoupling`)."""

    name = "plastic_bed"
    answers = {RELEASE: _BOTH, LOAD_HISTORY: _BOTH, HARMONIC_SWEEP: _BOTH}

    def free_vibration(self, model, structure, duration, initial_displacement,
                       sample_rate=2000.0):
        from pdamper.coupling.plastic import PlasticBedCoupling

        return PlasticBedCoupling.free_vibration(model, structure, duration,
                                                 initial_displacement, sample_rate)

    modal_free_vibration = free_vibration

    def load(self, model, structure, load, sample_rate=2000.0, tail=0.0):
        from pdamper.coupling.plastic import PlasticBedCoupling

        return PlasticBedCoupling.load(model, structure, load, sample_rate, tail)

    def stepped_sine(self, model, structure, load, frequency, direction, **options):
        # the block integrated event by event on the structure, no describing function
        from pdamper.coupling.plastic import stepped_sine

        return stepped_sine(model, structure, load, frequency, direction, **options)

    def sweep_cost(self, structure, frequencies, sweeps, max_cycles, drivers):
        # the block integrated step by step, in Python: its steps counted before the work
        import numpy as np

        from pdamper import resources
        from pdamper.coupling.plastic import (
            FRF_MAX_CYCLES,
            FRF_STEPS_PER_CYCLE,
            STEPS_PER_PERIOD,
        )
        from pdamper.models.plastic import BYTES_PER_SAMPLE, SECONDS_PER_STEP

        s = structure
        f = frequencies
        nf = int(f.size)
        cap = FRF_MAX_CYCLES if max_cycles is None else int(max_cycles)
        # a step runs until steady: about four decay times 1 / (zeta w) of the slowest mode
        tau = float(np.max(1.0 / (s.damping_ratios * s.angular_frequencies)))
        f_max = float(np.max(s.angular_frequencies)) / (2.0 * np.pi)
        per = np.array([min(cap, max(30.0, 4.0 * fk * tau))
                        * max(FRF_STEPS_PER_CYCLE, STEPS_PER_PERIOD * f_max / fk) for fk in f])
        drivers = [*drivers, ("max_cycles", cap / FRF_MAX_CYCLES)]
        return resources.Cost(
            "the plastic block's forced response", float(per.sum()) * sweeps *
            SECONDS_PER_STEP, float(per.max()) * BYTES_PER_SAMPLE,
            f"{nf} frequencies x {sweeps} sweeps, {per.sum() * sweeps:.3g} steps",
            tuple(drivers), runs=max(1, nf * sweeps),
            longest=float(per.max()) * SECONDS_PER_STEP,
            remedy="give frequency fewer values or lower max_cycles")


register(PseudoForce, CoSimulation, PlasticBed)
