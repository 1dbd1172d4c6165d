"""Interface strength: closed-form domains and the n x n spring sub-model (manuscript 2.1).

Local interface frame: y1, y2 in the interface plane (sides l1, l2), y3 the normal.
Forces f1, f2 (shear), f3 (normal, tension positive), moments m1, m2 (bending), m3 (torsion).
The spring sub-model divides the interface into n x n rectangles, each carrying an
elastic-perfectly-plastic spring: no-tension (or tensile strength) in the normal direction,
Mohr-Coulomb (Eq. 7) with a circular cap in shear. It is a rigid indenter on a
Winkler-Coulomb bed, driven by the relative displacements/rotations of the two blocks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stonedem.wall.return_map_kernel import torsion_constant_array

# manuscript Table A1: l1/l2, alpha (f1 only), alpha (f2 only), alpha (f1 = f2)
TABLE_A1 = np.array(
    [
        [0.1, 1.00, 2.56, 2.00],
        [0.2, 1.05, 2.44, 1.90],
        [0.5, 1.25, 1.92, 1.70],
        [1.0, 1.43, 1.43, 1.43],
        [2.0, 1.92, 1.25, 1.70],
        [5.0, 2.44, 1.05, 1.90],
        [10.0, 2.56, 1.00, 2.00],
    ]
)


def torsion_constant(l1, l2):
    """c_T: mean distance of the l1 x l2 rectangle from its centroid.

    Replaces the garbled manuscript Eq. 11 (reference YAML note); 0.0968 m for 0.3 x 0.2.
    Continuous as a side shrinks to zero: a segment of length l gives l/4 (edge contact).
    """
    a, b = np.broadcast_arrays(np.asarray(l1, dtype=float), np.asarray(l2, dtype=float))
    out = torsion_constant_array(np.ascontiguousarray(a).ravel(), np.ascontiguousarray(b).ravel())
    return float(out[0]) if a.ndim == 0 else out.reshape(a.shape)


def shear_strength(normal_force, mu, tensile_force=0.0):
    """f_su = mu (f_t - f_n), manuscript Eq. 10 (f_n < 0 in compression); 0 when detached."""
    return np.maximum(mu * (np.asarray(tensile_force) - np.asarray(normal_force)), 0.0)


def torsion_strength(normal_force, mu, l1, l2, tensile_force=0.0):
    """m_3u = c_T mu (f_t - f_n), manuscript Eq. 12."""
    return torsion_constant(l1, l2) * shear_strength(normal_force, mu, tensile_force)


def torsion_strength_with_bending(normal_force, mu, l1, l2, m1, m2):
    """Pure-torsion strength of a no-tension interface under bending (manuscript Fig. 10).

    Orduna & Lourenco (2005a): uniform compression over the reduced rectangle centred at the
    eccentricities e2 = |m1|/|f3| (along y2) and e1 = |m2|/|f3| (along y1).
    """
    n = np.abs(np.asarray(normal_force, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        e1 = np.where(n > 0, np.abs(m2) / n, np.inf)
        e2 = np.where(n > 0, np.abs(m1) / n, np.inf)
    r1 = np.clip(l1 - 2.0 * e1, 0.0, None)
    r2 = np.clip(l2 - 2.0 * e2, 0.0, None)
    return torsion_constant(r1, r2) * mu * n


@dataclass
class SpringHistory:
    """Resultants per step of a spring sub-model push: forces [N], moments [N m]."""

    drive: np.ndarray  # (steps, 6) imposed d1 d2 d3 delta1 delta2 delta3 [m, rad]
    forces: np.ndarray  # (steps, 6) f1 f2 f3 m1 m2 m3
    shear_stress: np.ndarray  # (n*n, 2) final tau1, tau2 per spring [Pa]
    x: np.ndarray
    y: np.ndarray

    @property
    def ultimate(self) -> np.ndarray:
        return self.forces[-1]


class SpringInterface:
    """An l1 x l2 interface as n x n elastic-perfectly-plastic Mohr-Coulomb springs."""

    def __init__(
        self, l1, l2, n=32, k_n=2.4e9, k_s=1.0e9, mu=0.7, tensile_strength=0.0, cohesion=None
    ):
        self.l1, self.l2, self.n = float(l1), float(l2), int(n)
        self.k_n, self.k_s, self.mu = float(k_n), float(k_s), float(mu)
        self.tensile_strength = float(tensile_strength)
        # Eq. 10: Mohr-Coulomb with the cap at sigma_t, i.e. c = sigma_t tan(phi)
        self.cohesion = self.mu * self.tensile_strength if cohesion is None else float(cohesion)
        h1, h2 = self.l1 / n, self.l2 / n
        xs = (np.arange(n) + 0.5) * h1 - self.l1 / 2
        ys = (np.arange(n) + 0.5) * h2 - self.l2 / 2
        self.x, self.y = (g.ravel() for g in np.meshgrid(xs, ys, indexing="ij"))
        self.dA = h1 * h2

    @property
    def area(self):
        return self.l1 * self.l2

    def spring_displacements(self, d):
        """Rigid-indenter kinematics: spring relative displacements (u1, u2, u3)."""
        d1, d2, d3, t1, t2, t3 = d
        return d1 - t3 * self.y, d2 + t3 * self.x, d3 + t1 * self.y - t2 * self.x

    def normal_stress(self, u3):
        """No-tension (or tensile strength) elastic springs; beyond sigma_t a spring detaches."""
        s = self.k_n * u3
        return np.where(s > self.tensile_strength, 0.0, s)

    def resultants(self, sigma, tau1, tau2):
        dA, x, y = self.dA, self.x, self.y
        return np.array(
            [
                tau1.sum() * dA,
                tau2.sum() * dA,
                sigma.sum() * dA,
                (sigma * y).sum() * dA,
                -(sigma * x).sum() * dA,
                (x * tau2 - y * tau1).sum() * dA,
            ]
        )

    def push(self, path, normal_stress=None) -> SpringHistory:
        """Drive the springs along ``path`` (steps x 6 relative displacements/rotations).

        ``normal_stress`` (scalar or per spring, compression negative) prescribes the normal
        stresses instead of the normal springs (uniform stress of a resultant f3, or uniform
        stress over a reduced rectangle, manuscript 2.1.3); then path columns 2-4 are unused.
        """
        path = np.atleast_2d(np.asarray(path, dtype=float))
        up = np.zeros((2, self.x.size))  # plastic slip
        out = np.empty((len(path), 6))
        tau = np.zeros((2, self.x.size))
        for k, d in enumerate(path):
            u1, u2, u3 = self.spring_displacements(d)
            if normal_stress is None:
                sigma = self.normal_stress(u3)
            else:
                sigma = np.broadcast_to(np.asarray(normal_stress, dtype=float), self.x.shape)
            # manuscript Eq. 7, circular cap |tau| <= c - mu sigma; detached springs carry nothing
            cap = np.maximum(self.cohesion - self.mu * sigma, 0.0)
            if normal_stress is None:
                cap = np.where(self.k_n * u3 > self.tensile_strength, 0.0, cap)
            trial = self.k_s * (np.array([u1, u2]) - up)
            mag = np.hypot(trial[0], trial[1])
            scale = np.where(mag > cap, cap / np.where(mag > 0, mag, 1.0), 1.0)
            tau = trial * scale
            # plastic slip so that k_s (u - up) = tau
            up = np.array([u1, u2]) - tau / self.k_s
            out[k] = self.resultants(sigma, tau[0], tau[1])
        return SpringHistory(path, out, tau.T.copy(), self.x, self.y)

    def uniform_stress(self, normal_force):
        return normal_force / self.area

    def reduced_area_stress(self, normal_force, m1, m2):
        """Uniform compression over the reduced rectangle of the eccentricities (Fig. 10)."""
        n = abs(normal_force)
        e2 = abs(m1) / n * np.sign(m1)  # centre of compression along y2
        e1 = -abs(m2) / n * np.sign(m2)  # along y1 (m2 = -sum sigma x dA)
        r1 = self.l1 - 2 * abs(e1)
        r2 = self.l2 - 2 * abs(e2)
        inside = (np.abs(self.x - e1) <= r1 / 2) & (np.abs(self.y - e2) <= r2 / 2)
        sigma = np.zeros_like(self.x)
        if inside.any():
            sigma[inside] = normal_force / (inside.sum() * self.dA)
        return sigma, (e1, e2)


def ramp(direction, magnitude, steps=40):
    """Radial path 0 -> magnitude * direction over ``steps`` steps (6 components)."""
    direction = np.asarray(direction, dtype=float)
    return np.linspace(0.0, 1.0, steps + 1)[1:, None] * magnitude * direction[None, :]


def shear_ultimate(spring: SpringInterface, normal_force, angle, magnitude=None, steps=40):
    """Ultimate (f1, f2) for relative shear displacement at ``angle`` to y1 (Fig. 4-5)."""
    if magnitude is None:
        magnitude = 50 * spring.mu * abs(normal_force) / (spring.k_s * spring.area)
    path = ramp([np.cos(angle), np.sin(angle), 0, 0, 0, 0], magnitude, steps)
    return spring.push(path, spring.uniform_stress(normal_force)).ultimate[:2]


def torsion_shear_domain(
    spring: SpringInterface,
    normal_force,
    shear_angle=0.0,
    n_points=19,
    steps=40,
    normal_stress=None,
    centre=(0.0, 0.0),
):
    """Points (|f|/f_su, |m3|/m3_u) of the torsion-shear domain (Fig. 8-9, A4).

    Each point is a radial push: shear displacement along ``shear_angle`` combined with a
    relative rotation, the ratio swept from pure shear to pure torsion.
    """
    sigma = spring.uniform_stress(normal_force) if normal_stress is None else normal_stress
    f_su = spring.mu * abs(normal_force) + spring.cohesion * spring.area
    c_T = torsion_constant(spring.l1, spring.l2)
    m3_u = c_T * f_su
    slip = 50 * f_su / (spring.k_s * spring.area)
    points = []
    for phi in np.linspace(0.0, np.pi / 2, n_points):
        d = [
            np.cos(phi) * np.cos(shear_angle),
            np.cos(phi) * np.sin(shear_angle),
            0,
            0,
            0,
            np.sin(phi) / c_T,
        ]
        # rotation about ``centre``: translate the drive so the twist centre is there
        d[0] += d[5] * centre[1]
        d[1] -= d[5] * centre[0]
        res = spring.push(ramp(d, slip, steps), sigma).ultimate
        points.append((np.hypot(res[0], res[1]) / f_su, abs(res[5]) / m3_u))
    return np.array(points)


def fit_alpha(points):
    """Exponent of (m3/m3u)^alpha + (f/fsu)^2 = 1 (Eq. A4) enclosing the same area as the domain.

    ``points``: (f/f_su, m3/m3_u) from pure shear to pure torsion. The area-equivalent fit does
    not depend on how the points are spread along the boundary.
    """
    f, m = points[:, 0], points[:, 1]
    order = np.argsort(f)
    f_all = np.concatenate([[0.0], f[order], [1.0]])
    m_all = np.concatenate([[1.0], m[order], [0.0]])
    target = np.trapezoid(m_all, f_all)
    fg = np.linspace(0.0, 1.0, 4001)
    lo, hi = 0.3, 6.0
    for _ in range(60):  # the area grows with alpha
        mid = 0.5 * (lo + hi)
        area = np.trapezoid((1 - fg**2) ** (1 / mid), fg)
        lo, hi = (mid, hi) if area < target else (lo, mid)
    return 0.5 * (lo + hi)


def torsion_vs_tensile_strength(spring_kwargs, normal_force, tensile_strengths, steps=30):
    """Pure-torsion strength of the spring model for increasing sigma_t (Fig. A1) vs Eq. 12."""
    numeric, analytic = [], []
    for st in tensile_strengths:
        sp = SpringInterface(**{**spring_kwargs, "tensile_strength": st})
        c_T = torsion_constant(sp.l1, sp.l2)
        slip = 50 * (sp.mu * abs(normal_force) + sp.cohesion * sp.area) / (sp.k_s * sp.area)
        res = sp.push(
            ramp([0, 0, 0, 0, 0, 1 / c_T], slip, steps), sp.uniform_stress(normal_force)
        ).ultimate
        numeric.append(abs(res[5]))
        analytic.append(float(torsion_strength(normal_force, sp.mu, sp.l1, sp.l2, st * sp.area)))
    return np.array(numeric), np.array(analytic)


def bending_push(spring: SpringInterface, normal_force, axis=1, rotation=None, steps=60):
    """Normal force held at ``normal_force`` while the relative rotation about y``axis`` grows.

    Returns (rotations, moments): the moment tends to |f3| l/2 (manuscript Eq. 9, l_c = l/2).
    """
    length = spring.l2 if axis == 1 else spring.l1
    if rotation is None:
        rotation = 200 * abs(normal_force) / (spring.k_n * spring.area * length)
    rots = np.linspace(0, rotation, steps + 1)[1:]
    moments = []
    for th in rots:
        d = np.zeros(6)
        d[3 if axis == 1 else 4] = th
        lo, hi = -10 * abs(normal_force) / (spring.k_n * spring.area) - th * length, th * length
        for _ in range(80):  # bisection on d3: sum of normal stresses = normal_force
            d[2] = 0.5 * (lo + hi)
            f3 = spring.normal_stress(spring.spring_displacements(d)[2]).sum() * spring.dA
            lo, hi = (d[2], hi) if f3 < normal_force else (lo, d[2])
        sig = spring.normal_stress(spring.spring_displacements(d)[2])
        r = spring.resultants(sig, 0 * sig, 0 * sig)
        moments.append(abs(r[3 if axis == 1 else 4]))
    return rots, np.array(moments)
