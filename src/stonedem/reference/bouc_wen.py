"""The Bouc-Wen sliding block (thesis Eq. 5.6-5.7) under a sampled accelerogram, compiled.

The comparison curve of the record_sliding validation:
:func:`stonedem.reference.analytic.bouc_wen_sliding` integrates it with LSODA in 12 s of Python per
record (the system is stiff: the elastic frequency sqrt(mu g / u_y) is ~2000 rad/s and, as |z| -> 1,
the z equation's own rate n |v| / u_y reaches 1e7-1e8 1/s). Here: BDF2 (stiffly accurate, so the
saturating z is damped, not rung) on a fixed grid of ``substeps`` steps per sample interval, where
a_g is linear, the first step backward Euler; each step solves for (v, z) by Newton's method on
the 2 x 2 system, then u. The LSODA version stays the reference; tests hold this one to it.
Imported by :mod:`stonedem.reference.analytic` only.
"""

from numba import njit

from stonedem.kernels import JIT_OPTIONS

NEWTON_STEPS = 50
NEWTON_TOLERANCE = 1e-13  # on the z update (dimensionless) and v update / (1 m/s)


@njit(**JIT_OPTIONS)
def bouc_wen_rate(v, z, u_y, gamma, beta, n):
    """z' and its partial derivatives (d/dv, d/dz); thesis Eq. 5.7:
    u_y z' = u' - gamma |u'| |z|^(n-1) z - beta u' |z|^n."""
    az = abs(z)
    pn1 = az ** (n - 1.0)
    pn = pn1 * az
    sv = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
    sz = 1.0 if z > 0.0 else (-1.0 if z < 0.0 else 0.0)
    rate = (v - gamma * abs(v) * pn1 * z - beta * v * pn) / u_y
    d_v = (1.0 - gamma * sv * pn1 * z - beta * pn) / u_y
    d_z = -(gamma * abs(v) + beta * v * sz) * n * pn1 / u_y
    return rate, d_v, d_z


@njit(**JIT_OPTIONS)
def implicit_step(c_v, c_z, weight, a_new, v0, z0, mu_g, u_y, gamma, beta, n):
    """Solve v = c_v + weight (-a_new - mu g z), z = c_z + weight z'(v, z) by Newton's method
    from (v0, z0); returns (v, z, converged)."""
    v, z = v0, z0
    for _ in range(NEWTON_STEPS):
        rate, d_v, d_z = bouc_wen_rate(v, z, u_y, gamma, beta, n)
        r1 = v - c_v + weight * (a_new + mu_g * z)
        r2 = z - c_z - weight * rate
        j11, j12 = 1.0, weight * mu_g
        j21, j22 = -weight * d_v, 1.0 - weight * d_z
        det = j11 * j22 - j12 * j21
        dv = (r1 * j22 - r2 * j12) / det
        dz = (j11 * r2 - j21 * r1) / det
        v -= dv
        z -= dz
        if abs(dz) < NEWTON_TOLERANCE and abs(dv) < NEWTON_TOLERANCE:
            return v, z, True
    return v, z, False


@njit(**JIT_OPTIONS)
def bouc_wen_history(time, accel, mu, g, u_y, gamma, beta, n, substeps, u_out, v_out):
    """Integrate from rest (u = v = z = 0); fill u_out, v_out at the sample instants.

    Returns the number of steps whose Newton iteration did not converge (0 normally)."""
    mu_g = mu * g
    u, v, z = 0.0, 0.0, 0.0
    u_prev, v_prev, z_prev = 0.0, 0.0, 0.0
    first = True
    failures = 0
    u_out[0], v_out[0] = 0.0, 0.0
    for i in range(len(time) - 1):
        h = (time[i + 1] - time[i]) / substeps
        slope = (accel[i + 1] - accel[i]) / (time[i + 1] - time[i])
        for k in range(substeps):
            a_new = accel[i] + slope * (k + 1) * h
            if first:  # backward Euler: y1 = y0 + h f(y1)
                c_u, c_v, c_z, weight = u, v, z, h
            else:  # BDF2: y_{k+1} = (4 y_k - y_{k-1}) / 3 + 2/3 h f(y_{k+1})
                c_u = (4.0 * u - u_prev) / 3.0
                c_v = (4.0 * v - v_prev) / 3.0
                c_z = (4.0 * z - z_prev) / 3.0
                weight = 2.0 * h / 3.0
            v_new, z_new, ok = implicit_step(
                c_v, c_z, weight, a_new, v, z, mu_g, u_y, gamma, beta, n
            )
            if not ok:
                failures += 1
            u_prev, v_prev, z_prev = u, v, z
            u, v, z = c_u + weight * v_new, v_new, z_new
            first = False
        u_out[i + 1], v_out[i + 1] = u, v
    return failures
