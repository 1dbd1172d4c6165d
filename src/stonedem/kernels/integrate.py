"""Central-difference integration and driven-body kinematics (thesis 3.9).

The central difference method of thesis Eq. 3.16, U(t+dt) = dt^2 M^-1 F(t) + 2U(t) - U(t-dt),
is written in its equivalent velocity form (leapfrog): with mid-step velocities
v(t+dt/2) = v(t-dt/2) + dt M^-1 F(t) (Eq. 3.13) and U(t+dt) = U(t) + dt v(t+dt/2) (Eq. 3.10).
M is diagonal (Eq. 3.17), so each body updates on its own. Driven bodies are not
integrated: their position and velocity are set from the base motion.
"""

from numba import njit

from stonedem.kernels import INLINE_OPTIONS
from stonedem.kernels.scalar import cos, sin

QUARTER_PI = 0.7853981633974483  # pi / 4, rounded down to a double


@njit(**INLINE_OPTIONS)
def cos_sin(x):
    """(cos x, sin x): on |x| <= pi/4 fdlibm's kernels (k_cos.c, k_sin.c of Sun's fdlibm 5.3, as in
    glibc's and musl's libm), polynomials with an error below 1 ulp and no argument reduction;
    beyond, libm's. A block's angle stays within pi/4 until long after it has collapsed, and
    libm's pair of calls costs about twice the two polynomials (it reduces the argument and
    dispatches on its range first)."""
    if not abs(x) <= QUARTER_PI:  # NaN too
        return cos(x), sin(x)
    z = x * x
    # sin x = x + x^3 (S1 + z (S2 + z (S3 + z (S4 + z (S5 + z S6)))))
    r = 8.33333333332248946124e-03 + z * (
        -1.98412698298579493134e-04
        + z
        * (
            2.75573137070700676789e-06
            + z * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10)
        )
    )
    s = x + z * x * (-1.66666666666666324348e-01 + z * r)
    # cos x = 1 - z/2 + z^2 (C1 + z (C2 + ... + z C6)), with 1 - z/2 summed so that its
    # rounding error is kept (k_cos.c's w = 1 - hz and ((1 - w) - hz))
    rc = z * (
        4.16666666666666019037e-02
        + z
        * (
            -1.38888888888741095749e-03
            + z
            * (
                2.48015872894767294178e-05
                + z
                * (
                    -2.75573143513906633035e-07
                    + z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)
                )
            )
        )
    )
    hz = 0.5 * z
    w = 1.0 - hz
    c = w + (((1.0 - w) - hz) + z * rc)
    return c, s


@njit(**INLINE_OPTIONS)
def update_world_vertices(
    n_body,
    vert_start,
    local_x,
    local_y,
    body_x,
    body_y,
    body_theta,
    world_x,
    world_y,
    cos_theta,
    sin_theta,
):
    """World coordinates of every vertex from body pose: w = x + R(theta) v_local [m].

    cos_theta, sin_theta (n_body,) receive each body's cos and sin of theta (:func:`cos_sin`; the
    time loop reuses them for its measures)."""
    for b in range(n_body):
        c, s = cos_sin(body_theta[b])
        body_world_vertices(
            b,
            c,
            s,
            vert_start,
            local_x,
            local_y,
            body_x,
            body_y,
            world_x,
            world_y,
            cos_theta,
            sin_theta,
        )


@njit(**INLINE_OPTIONS)
def body_world_vertices(
    b, c, s, vert_start, local_x, local_y, body_x, body_y, world_x, world_y, cos_theta, sin_theta
):
    """Body b's world vertices from its position and the cos c and sin s of its angle [m]; c and
    s kept in cos_theta, sin_theta."""
    cos_theta[b] = c
    sin_theta[b] = s
    for k in range(vert_start[b], vert_start[b + 1]):
        world_x[k] = body_x[b] + c * local_x[k] - s * local_y[k]
        world_y[k] = body_y[b] + s * local_x[k] + c * local_y[k]


@njit(**INLINE_OPTIONS)
def drive_bodies(
    n_body,
    body_driven,
    ref_x,
    ref_y,
    ref_theta,
    d_h,
    v_h,
    d_v,
    v_v,
    body_x,
    body_y,
    body_theta,
    body_vx,
    body_vy,
    body_omega,
):
    """Set driven bodies to their reference pose shifted by the base displacement (d_h, d_v) [m]."""
    for b in range(n_body):
        if body_driven[b]:
            body_x[b] = ref_x[b] + d_h
            body_y[b] = ref_y[b] + d_v
            body_theta[b] = ref_theta[b]
            body_vx[b] = v_h
            body_vy[b] = v_v
            body_omega[b] = 0.0


@njit(**INLINE_OPTIONS)
def central_difference_step(
    n_body,
    body_driven,
    inv_mass,
    inv_inertia,
    gravity,
    kick,
    dt,
    force_x,
    force_y,
    torque,
    body_x,
    body_y,
    body_theta,
    body_vx,
    body_vy,
    body_omega,
):
    """Advance free bodies one step: kick mid-step velocities by ``kick`` F/m, drift by dt v.

    inv_mass, inv_inertia: 1 / mass and 1 / moment of inertia of each body [kg-1], [kg-1 m-2]
    (multiplied: a division costs several multiplications and the masses do not change)
    gravity: acceleration of gravity, acting along -y [m s-2]
    kick: velocity update interval, dt except dt/2 on the first step [s]
    body_vx, body_vy, body_omega hold v(t - dt/2) on entry and v(t + dt/2) on exit
    """
    for b in range(n_body):
        if body_driven[b]:
            continue
        body_vx[b] += kick * force_x[b] * inv_mass[b]  # thesis Eq. 3.7
        body_vy[b] += kick * (force_y[b] * inv_mass[b] - gravity)  # thesis Eq. 3.8
        body_omega[b] += kick * torque[b] * inv_inertia[b]  # thesis Eq. 3.9
        body_x[b] += dt * body_vx[b]
        body_y[b] += dt * body_vy[b]
        body_theta[b] += dt * body_omega[b]
