"""The stepping loop of :func:`pdamper.coupling.loads.simulate_load` (numba; imported
where used, so that importing the coupling stays fast)."""

from __future__ import annotations

from numba import njit


@njit(cache=True)
def advance(z, zdot, u, y_b, phi, p_mat, g0, g1, a_mat, b_mat, dd, me, d, m_eff, k0, steps,
            det, h):  # pragma: no cover - compiled
    """Step ``z[k+1] = P z[k] + G0 u[k] + G1 (u[k+1] - u[k])`` from sample ``k0`` with fixed
    coefficients (``d``, ``m_eff`` recorded per sample) until the container's displacement
    ``phi . q + y_b`` has a minimum after a maximum; returns the sample reached (the one
    after the minimum; ``steps`` at the end).

    ``det`` (updated in place): the displacement at the two previous samples, the time [s]
    and displacement of the last maximum, the time of the last minimum (kept by the caller),
    the displacement of the minimum found.
    """
    n = phi.size
    for k in range(k0, steps):
        du = u[k + 1] - u[k]
        z[k + 1] = p_mat @ z[k] + g0 @ u[k] + g1 @ du
        zdot[k + 1] = a_mat @ z[k + 1] + b_mat @ u[k + 1]
        dd[k + 1] = d
        me[k + 1] = m_eff
        xc = y_b[k + 1]
        for i in range(n):
            xc += phi[i] * z[k + 1, i]
        prev2 = det[0]
        prev = det[1]
        det[0] = prev
        det[1] = xc
        if k >= 1:
            if prev > prev2 and prev >= xc:  # a maximum at sample k
                det[2] = k * h
                det[3] = prev
            elif prev < prev2 and prev <= xc and det[3] == det[3]:  # a minimum after one
                det[5] = prev
                return k + 1
    return steps
