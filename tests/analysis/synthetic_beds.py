"""Synthetic bed trajectories for the motion-mode classifier: a rigid block in a box.

A block of mass ``m`` moves in a box ``x_c = X sin(W t)`` of clearance ``h`` under gravity;
it rests on the bottom while the bottom pushes it (``a_c >= -g``), on the lid while the lid
holds it down (``a_c <= -g``), flies on parabolas otherwise, and at an impact keeps
``-e`` times its velocity relative to the wall (``e = 0``: the paper's inelastic
collect-and-collide block; ``e`` close to 1: a rattling bed; ``random_e``: a new ``e`` at
every impact, the irregular impacts of a scattering bed). A real bed collects over many
particle collisions: the impulse of an impact reaches the container spread over
``collect`` cycles (the DEM beds of the benchmark press on a wall 17-50 % of a cycle; an
elastic rebound is short: ``collect = 0``). Independent of the classifier and of the
analytical model (a time-stepped simulation with exact contact states), it records what a
DEM run records: the height of the bed in the container and the force on the container,
averaged over each sample interval.
"""

from __future__ import annotations

import math

import numpy as np

from pdamper.analysis.dem_modes import BedSignals

G = 9.80665
REST = 0.010  # height of the bed's centre above the bottom when resting [m]


def block_in_box(frequency: float, amplitude: float, clearance: float = 0.1,
                 restitution: float = 0.0, cycles: int = 16, samples_per_cycle: int = 200,
                 substeps: int = 40, mass: float = 0.132, random_e=None,
                 collect: float = 0.15, seed: int = 0) -> BedSignals:
    rng = np.random.default_rng(seed)
    w = 2 * math.pi * frequency
    n = cycles * samples_per_cycle
    dt = 1.0 / frequency / samples_per_cycle / substeps
    z, v = 0.0, amplitude * w  # bed bottom face, on the container bottom at t = 0
    state = "bottom"
    t_s = np.arange(n + 1) / (samples_per_cycle * frequency)
    height = np.empty(n + 1)
    force = np.zeros(n + 1)
    height[0] = REST
    t = 0.0

    def wall(t):
        return amplitude * math.sin(w * t), amplitude * w * math.cos(w * t), \
            -amplitude * w * w * math.sin(w * t)

    def e():
        return rng.uniform(*random_e) if random_e is not None else restitution

    spread = max(1, round(collect * samples_per_cycle))
    pending = np.zeros(n + spread + 2)  # impulses arriving at later samples [N s]
    for k in range(1, n + 1):
        impulse = 0.0
        f_sum = 0.0
        for _ in range(substeps):
            t += dt
            zc, vc, ac = wall(t)
            if state == "bottom":
                if ac >= -G:
                    z, v = zc, vc
                    f_sum += -mass * (ac + G)
                    continue
                state = "flight"
            elif state == "lid":
                if ac <= -G:
                    z, v = zc + clearance, vc
                    f_sum += -mass * (ac + G)
                    continue
                state = "flight"
            v -= G * dt
            z += v * dt
            if z <= zc and v < vc:
                v_new = vc - e() * (v - vc)
                impulse -= mass * (v_new - v)  # the bed pushes the container down
                z, v = zc, v_new
                if v_new - vc < 1e-9 and ac >= -G:
                    state = "bottom"
            elif z >= zc + clearance and v > vc:
                v_new = vc - e() * (v - vc)
                impulse -= mass * (v_new - v)  # positive: the lid is pushed up
                z, v = zc + clearance, v_new
                if vc - v_new < 1e-9 and ac <= -G:
                    state = "lid"
        zc, _, _ = wall(t)
        height[k] = z - zc + REST
        pending[k:k + spread] += impulse / spread
        force[k] = f_sum / substeps + pending[k] / (substeps * dt)
    return BedSignals(t_s, height, force, frequency, mass, 0.005, clearance + 2 * REST, G)
