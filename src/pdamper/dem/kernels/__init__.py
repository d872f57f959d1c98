"""numba kernels of the DEM engine, split by concern.

===================  ==================================================================
module               what
===================  ==================================================================
``state``            named bundles of inputs (NamedTuples) and records of mutable state
``motion``           container motion: harmonic, sampled table, 1-DOF structure
``search``           linked cells + half Verlet list, contact history carried over
``forces``           :func:`~pdamper.dem.kernels.forces.contact_force`, the one
                     per-contact law of sphere-sphere and sphere-wall contacts, and the
                     loop over all contacts
``sampling``         samples, snapshots, force windows, energy ledger, failure checks
``verlet``           velocity Verlet (fixed step)
``gear``             variable-step fifth-order Gear predictor-corrector (the paper's)
``flights``          free flights: spheres that cannot touch anything before a horizon
                     leave the Gear step and move on their exact parabola
===================  ==================================================================

Everything is compiled with ``numba.njit(cache=True)``. The Python driver
(:mod:`pdamper.dem.simulation`) allocates every array once and calls ``*_start`` and then
``*_advance`` repeatedly, each call integrating up to a given landing on the half-sample
grid (a chunk of a fraction of a second of wall time), so that Python can handle signals
and stop a run between chunks; no Python and no allocation happens per step. The loops are
serial and in a fixed order: the same inputs give bit-identical results, however the run
is cut into chunks. The force loop is inlined into the integrators (``inline="always"``)
and the hot kernels use numpy's error model (no zero-division branches; the NaN checks
catch what a division by zero would produce).
"""
