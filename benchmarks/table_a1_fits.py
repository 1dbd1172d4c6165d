"""Which fitting procedure reproduces manuscript Table A1? (issue 15, item 5)

The manuscript fits the exponent alpha of Eq. A4, (m3/m3u)^alpha + (f/fsu)^2 = 1, to the
torsion-shear domain of its spring interface, but does not say how. We compute the domain
(stonedem.wall.interface.torsion_shear_domain: 37 radial pushes of a rigid-plastic spring grid,
normal force -240 N, mu = 0.7) and fit alpha by six criteria, on four spring grids, with two
readings of the "f1 = f2" column and two normalisations of m3:

- criteria: ``area`` (ours: the curve encloses the domain's area), ``ls_m`` (least squares
  in m3 at the points' f), ``radial`` (least squares of the distance from the origin along
  each point's ray), ``ls_g`` (least squares of m^alpha + f^2 - 1), ``ray45`` (through the
  domain's point on the 45 degree ray), ``minimax`` (smallest largest radial miss);
- ``f1=f2``: drive at 45 degrees (ours), or the shear *force* at 45 degrees (the drive angle
  of each push bisected until f2 = f1);
- m3 normalised by c_T f_su (ours, Eq. 12) or by the grid's own pure-torsion strength.

Prints, per combination, the entries within 0.05 of the table (of 21) and the largest
error, and writes results/walls/table_a1_fits.csv. ``--quick``: grids of 8 and 16 springs.
"""

from __future__ import annotations

import itertools
import math
import sys
import time
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np
from scipy import optimize

from benchmarks import options
from stonedem.wall.interface import TABLE_A1, SpringInterface, fit_alpha, ramp, torsion_constant

DIRECTIONS = {"f1": 0.0, "f2": math.pi / 2, "f1=f2": math.pi / 4}
NORMAL_FORCE = -240.0
N_POINTS = 37
STEPS = 20
TOLERANCE = 0.05


def push_point(spring, phi, angle, slip, c_T):
    d = np.array(
        [
            math.cos(phi) * math.cos(angle),
            math.cos(phi) * math.sin(angle),
            0,
            0,
            0,
            math.sin(phi) / c_T,
        ]
    )
    res = spring.push(ramp(d, slip, STEPS), spring.uniform_stress(NORMAL_FORCE)).ultimate
    return res[0], res[1], res[5]


def domain(spring, direction, force_45=False):
    """(f, m3) of the radial pushes (unnormalised), pure shear to pure torsion."""
    f_su = spring.mu * abs(NORMAL_FORCE) + spring.cohesion * spring.area
    c_T = torsion_constant(spring.l1, spring.l2)
    slip = 50 * f_su / (spring.k_s * spring.area)
    points = []
    for phi in np.linspace(0.0, math.pi / 2, N_POINTS):
        angle = DIRECTIONS[direction]
        if force_45 and 0.0 < phi < math.pi / 2:  # bisect the drive angle until f2 = f1
            lo, hi = 0.0, math.pi / 2
            for _ in range(30):
                angle = 0.5 * (lo + hi)
                f1, f2, _ = push_point(spring, phi, angle, slip, c_T)
                lo, hi = (angle, hi) if f2 < f1 else (lo, angle)
        f1, f2, m3 = push_point(spring, phi, angle, slip, c_T)
        points.append((math.hypot(f1, f2), abs(m3)))
    return np.array(points), f_su, c_T * f_su


def ray_radius(theta, alpha):
    """Distance from the origin to the Eq. A4 curve along the ray at angle theta (f, m axes)."""
    c, s = np.cos(theta), np.sin(theta)
    lo, hi = np.zeros_like(theta), np.full_like(theta, 2.0)
    for _ in range(60):
        t = 0.5 * (lo + hi)
        inside = (t * s) ** alpha + (t * c) ** 2 < 1.0
        lo, hi = np.where(inside, t, lo), np.where(inside, hi, t)
    return 0.5 * (lo + hi)


def fits(points):
    """alpha by each criterion from normalised points (f, m)."""
    f, m = points[:, 0], points[:, 1]
    theta, radius = np.arctan2(m, f), np.hypot(f, m)
    inner = (f > 1e-9) & (m > 1e-9)
    bounded = {"bounds": (0.3, 6.0), "method": "bounded", "options": {"xatol": 1e-6}}

    def best(cost):
        return float(optimize.minimize_scalar(cost, **bounded).x)

    out = {
        "area": fit_alpha(points),
        "ls_m": best(lambda a: np.sum((m - np.clip(1 - f**2, 0, None) ** (1 / a)) ** 2)),
        "radial": best(lambda a: np.sum((radius - ray_radius(theta, a)) ** 2)),
        "ls_g": best(lambda a: np.sum((m[inner] ** a + f[inner] ** 2 - 1) ** 2)),
        "minimax": best(lambda a: np.max(np.abs(radius - ray_radius(theta, a)))),
    }
    # through the domain's point on the 45 degree ray (interpolated along the boundary)
    k = np.argsort(theta)
    r45 = float(np.interp(math.pi / 4, theta[k], radius[k]))
    out["ray45"] = best(lambda a: (ray_radius(np.array([math.pi / 4]), a)[0] - r45) ** 2)
    return out


def build_parser():
    parser = options.parser("python -m benchmarks.table_a1_fits", __doc__)
    parser.add_argument("--quick", action="store_true", help="grids of 8 and 16 springs only")
    parser.add_argument(
        "-o",
        "--output",
        type=options.path_arg,
        default="results/walls/table_a1_fits.csv",
        help="output table (.csv)",
    )
    return parser


def main(argv=None) -> int:
    """Options and output path checked first (one line, exit 2); then the fits."""
    args = build_parser().parse_args(argv)

    def command():
        output = options.output_file(args.output, "-o/--output", suffixes=(".csv",))
        return table_a1_fits(output, args.quick)

    return options.run(command)


def table_a1_fits(output: Path, quick: bool = False) -> int:
    grids = (8, 16) if quick else (8, 16, 32, 64)
    rows = []
    start = time.perf_counter()
    for n in grids:
        for ratio, *refs in TABLE_A1:
            spring = SpringInterface(ratio * 0.2, 0.2, n=n)
            for direction, ref in zip(DIRECTIONS, refs):
                readings = [("drive 45", False)] + (
                    [("force 45", True)] if direction == "f1=f2" else []
                )
                for reading, force_45 in readings:
                    raw, f_su, m3u = domain(spring, direction, force_45)
                    for norm in ("c_T f_su", "own torsion"):
                        scale = m3u if norm == "c_T f_su" else raw[-1, 1]
                        pts = np.column_stack([raw[:, 0] / f_su, raw[:, 1] / scale])
                        for criterion, alpha in fits(pts).items():
                            rows.append(
                                {
                                    "n": n,
                                    "l1_over_l2": ratio,
                                    "shear": direction,
                                    "reading": reading,
                                    "m3_normalised_by": norm,
                                    "criterion": criterion,
                                    "alpha": round(alpha, 4),
                                    "alpha_manuscript": ref,
                                    "error": round(alpha - ref, 4),
                                }
                            )
        print(f"n = {n}: {time.perf_counter() - start:.0f} s", flush=True)
    options.write_csv(output, rows)
    # the summary: per combination, f1=f2 read either way (the other columns as they are)
    print(
        f"\n{'n':>3} {'f1=f2 reading':14} {'m3 by':12} {'criterion':8} within/21  max|err|  "
        "worst entry"
    )
    keys = sorted({(r["n"], r["m3_normalised_by"], r["criterion"]) for r in rows})
    best = None
    for (n, norm, criterion), reading in itertools.product(keys, ("drive 45", "force 45")):
        pick = [
            r
            for r in rows
            if (r["n"], r["m3_normalised_by"], r["criterion"]) == (n, norm, criterion)
            and (r["reading"] == reading or r["shear"] != "f1=f2")
        ]
        errors = np.array([abs(r["error"]) for r in pick])
        worst = pick[int(np.argmax(errors))]
        within = int(np.sum(errors <= TOLERANCE))
        print(
            f"{n:>3} {reading:14} {norm:12} {criterion:8} {within:>5}    {errors.max():.3f}    "
            f"({worst['l1_over_l2']:g}, {worst['shear']}) {worst['alpha']:.2f} vs "
            f"{worst['alpha_manuscript']:.2f}"
        )
        if best is None or (within, -errors.max()) > best[0]:
            best = ((within, -errors.max()), n, reading, norm, criterion)
    (within, neg), n, reading, norm, criterion = best
    print(
        f"\nbest: n = {n}, f1=f2 as {reading}, m3 by {norm}, {criterion}: {within}/21 within "
        f"{TOLERANCE}, "
        f"max error {-neg:.3f}; {output}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())  # one-line errors, exit 2 on bad input, 130 on Ctrl-C
