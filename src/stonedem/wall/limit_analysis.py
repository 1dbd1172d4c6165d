"""Limit analysis of a wall model by linear programming: the collapse multiplier of the same
discrete model the pushover solves (a second solver, the pushover's test oracle).

Static theorem: the largest lambda for which interface actions f exist in equilibrium,
T^T H^T P f = T^T (F_D + lambda F_L) (the pushover's compatibility H, restraint reduction T
and loads; P: local -> global component order), inside every interface's strength domain:

- N <= f_t (tension positive); |m_b1| <= R l_c1, |m_b2| <= R l_c2, R = f_t - N (Eq. 9);
- (|m3| / M)^alpha + (f1^2 + f2^2) / F^2 <= 1, F = c A - mu N, M = c_T F (Eq. 10, 12, 14),
  c_T of the rectangle left in compression by the bending moments (Fig. 10).

The pushover's joints do not dilate (neither sliding nor rocking changes N), so their
collapse load depends on the normal forces at collapse, which a single LP cannot find: with
the caps linear in a free N (associated flow) the LP gives Orduña case 1 0.75 instead of
0.177, or no bound at all where restraints can prestress the wall. The caps are therefore
evaluated on a given state of actions (``caps_at``): the dead-load state (an estimate that
needs no pushover) or the pushover's own state at its peak. In the second reading the
pushover's peak is a feasible point of the LP, so lambda_LP >= lambda_pushover, with equality
exactly when the peak is the collapse load of the model under those caps: the oracle.

The convex shear-torsion domain enters through supporting planes generated where an LP
solution leaves it (Kelley's cutting planes: the solution is projected radially onto the
domain's boundary and the tangent plane there is added), from the box |f1|, |f2| <= F,
|m3| <= M. Every plane lies outside the domain, so every round's lambda is an upper bound; the
rounds stop when no interface exceeds its domain by more than ``domain_tolerance``. HiGHS
(``highspy``: its interior point method without crossover, which scipy's ``linprog`` does not
offer) solves each round; rows are added to the model, nothing is rebuilt.
"""

from __future__ import annotations

import contextlib
import os
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from stonedem.entry import check_interrupt
from stonedem.wall.return_map_kernel import torsion_constant_array


class LimitAnalysisError(RuntimeError):
    """The LP has no answer (no equilibrium at lambda = 0, or no mechanism)."""


@dataclass
class LimitAnalysisResult:
    lambda_limit: float  # collapse multiplier (last round; an upper bound of the exact LP)
    converged: bool
    status: str  # why the rounds stopped, in words
    rounds: int  # LP solves
    cuts: int  # supporting planes of the shear-torsion domains
    domain_excess: float  # max over interfaces of (|m3|/M)^alpha + (r/F)^2 - 1 (last LP)
    seconds: float
    forces: np.ndarray  # (ni, 6) local actions at collapse (t1, t2, n, b1, b2, tor)
    history: np.ndarray  # (rounds,) lambda of every round


def radial_boundary_points(u, v, alpha):
    """Points of the boundary v^alpha + u^2 = 1 on the rays through (u, v) >= 0 outside it."""
    lo, hi = np.zeros_like(u), np.ones_like(u)
    for _ in range(50):  # (t v)^alpha + (t u)^2 grows with t
        t = 0.5 * (lo + hi)
        inside = (t * v) ** alpha + (t * u) ** 2 <= 1.0
        lo, hi = np.where(inside, t, lo), np.where(inside, hi, t)
    return lo * u, lo * v


def tangent_normals(u, v, alpha):
    """Unit outward normals (n_u, n_v) of v^alpha + u^2 = 1 at its points (u, v)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        n_v = np.where(
            v > 0,
            alpha * np.where(v > 0, v, 1.0) ** (alpha - 1.0),
            np.where(alpha <= 1.0, 1.0, 0.0),
        )
    n_u = 2.0 * u
    norm = np.hypot(n_u, n_v)
    return n_u / norm, n_v / norm


def domain_excess(f, F, M, alpha):
    """(|m3|/M)^alpha + (f1^2 + f2^2)/F^2 - 1 of local actions ``f`` (0 where F = M = 0)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.where(F > 0, np.hypot(f[:, 0], f[:, 1]) / F, 0.0)
        v = np.where(M > 0, np.abs(f[:, 5]) / M, 0.0)
    return v**alpha + u**2 - 1.0, u, v


def supporting_planes(f, F, c_T, u, v, alpha, which, turn=0.0):
    """CSR rows over (f, lambda) and upper bounds of the tangent planes at the radial
    projections of interfaces ``which``: n_u (cos phi f1 + sin phi f2) + n_v sign m3 / c_T <= b
    F."""
    ub, vb = radial_boundary_points(u[which], v[which], alpha[which])
    n_u, n_v = tangent_normals(ub, vb, alpha[which])
    phi = np.arctan2(f[which, 1], f[which, 0]) + turn
    sign = np.where(f[which, 5] < 0, -1.0, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        m3 = np.where(n_v > 0, n_v * sign / np.where(c_T[which] > 0, c_T[which], np.inf), 0.0)
    cols = np.column_stack([6 * which, 6 * which + 1, 6 * which + 5])
    vals = np.column_stack([n_u * np.cos(phi), n_u * np.sin(phi), m3])
    return cols, vals, (n_u * ub + n_v * vb) * F[which]


def caps_of_state(model, f):
    """Caps of every interface on the actions ``f`` (ni, 6): R = f_t - N, F = c A - mu N,
    c_T (Fig. 10), plus f_t and alpha."""
    sec, st = model.sec, model.strength
    ni = model.panel.n_interfaces

    def per(v):
        return np.ascontiguousarray(np.broadcast_to(np.asarray(v, dtype=float), (ni,)))

    area, width, depth = per(sec.area), per(sec.width), per(sec.depth)
    f_t = per(st.tensile_strength) * area
    N = f[:, 2]
    R = np.maximum(f_t - N, 0.0)
    F = np.maximum(per(st.cohesion) * area - per(st.mu) * N, 0.0)
    fig10 = np.ones(ni, bool) if st.torsion_all_joints else f_t <= 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        w_eff = np.where(fig10 & (R > 0), np.maximum(width - 2 * np.abs(f[:, 4]) / R, 0.0), width)
        s_eff = np.where(fig10 & (R > 0), np.maximum(depth - 2 * np.abs(f[:, 3]) / R, 0.0), depth)
    c_T = torsion_constant_array(np.ascontiguousarray(w_eff), np.ascontiguousarray(s_eff))
    # a rectangle bent down to a speck (c_T 1e-18 m on S23) carries no torsion: M = 0 there
    # keeps the planes' m3 / c_T coefficients finite (HiGHS refuses values over 1e15)
    c_T = np.where(c_T > 1e-6 * np.minimum(width, depth), c_T, 0.0)
    return f_t, R, F, c_T, per(st.alpha)


@contextlib.contextmanager
def _quiet_stdout():
    """HiGHS prints a banner on stdout when created; keep a CLI's stdout clean."""
    fd = os.dup(1)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 1)
            yield
    finally:
        os.dup2(fd, 1)
        os.close(fd)


def _highs(cost, lo, hi, A_eq, b_eq):
    import highspy

    with _quiet_stdout():
        h = highspy.Highs()
    h.setOptionValue("output_flag", False)
    h.setOptionValue("solver", "ipm")
    h.setOptionValue("run_crossover", "off")
    lp = highspy.HighsLp()
    A = A_eq.tocsc()
    lp.num_col_, lp.num_row_ = A.shape[1], A.shape[0]
    lp.col_cost_, lp.col_lower_, lp.col_upper_ = cost, lo, hi
    lp.row_lower_, lp.row_upper_ = b_eq, b_eq
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_, lp.a_matrix_.index_, lp.a_matrix_.value_ = A.indptr, A.indices, A.data
    h.passModel(lp)
    return h


# the pushover's plateau counts as proven when the limit analysis on its own caps lies this
# close above it (tests/wall/test_tables.py holds every table case to it)
ORACLE_TOLERANCE = 0.01

# planes per interface and round: at the shear direction of the solution and turned +-20 deg
# (chee_liang_2_3: lambda within 2e-4 of its limit in 7 rounds instead of 11)
TURNS = (0.0, -0.35, 0.35)
# a plane whose slack exceeds this fraction of its bound at the round's answer is dropped: the
# LP stays an outer bound, the interior point solves fewer rows (chee_liang_10_11 8.3 -> 5.0 s)
DROP = 0.05


def limit_multiplier(
    model, caps_at, domain_tolerance=1e-3, lambda_tolerance=1e-4, max_rounds=60
) -> LimitAnalysisResult:
    """Collapse multiplier of ``model`` (a ``WallModel``) by the static theorem, its caps
    evaluated on the actions ``caps_at`` (ni, 6): the pushover's interface forces at its peak,
    or the dead-load state (``stonedem.wall.pushover.dead_load_state``).

    Each round solves the LP by HiGHS's interior point method without crossover: its answer is
    the centre of the optimal face, not a vertex (at a vertex every idle joint sits at a corner
    of its box and asks for a plane), and adds planes where that answer leaves a domain. The
    rounds stop when no interface exceeds its domain by more than ``domain_tolerance`` or when
    lambda moves by less than ``lambda_tolerance`` (relative) in two rounds in a row. Raises
    ``LimitAnalysisError`` when the dead load has no equilibrium inside the caps or when the
    restraints leave no mechanism (the LP is unbounded)."""
    import highspy

    t0 = time.perf_counter()
    model.use("live")
    ni = model.panel.n_interfaces
    f_t, R, F, c_T, alpha = caps_of_state(model, np.asarray(caps_at, dtype=float))
    M = c_T * F

    # equilibrium T^T H^T P f - lambda T^T F_L = T^T F_D, rows scaled to unit norm
    perm = model.sec.perm
    P = sp.csr_matrix(
        (np.ones(6 * ni), ((6 * np.arange(ni)[:, None] + perm).ravel(), np.arange(6 * ni))),
        shape=(6 * ni, 6 * ni),
    )
    A_eq = sp.hstack([model.TT @ model.H.T @ P, -model.reduce(model.live_load)[:, None]]).tocsr()
    norms = np.sqrt(np.asarray(A_eq.multiply(A_eq).sum(axis=1)).ravel())
    norms = np.where(norms > 0, norms, 1.0)
    A_eq = sp.diags(1.0 / norms) @ A_eq
    b_eq = model.reduce(model.dead_load) / norms

    n_col = 6 * ni + 1
    lo, hi = np.full(n_col, -np.inf), np.full(n_col, np.inf)
    # an F below HiGHS's feasibility tolerance (1e-7 of the largest) is numerical dust
    negligible = 1e-7 * max(float(F.max(initial=0.0)), 1e-300)
    counted = F > negligible
    lever = model.sec.lever
    hi[2 : 6 * ni : 6] = f_t  # N <= f_t
    for comp, cap in ((0, F), (1, F), (5, M)):  # Eq. 10-12
        lo[comp : 6 * ni : 6], hi[comp : 6 * ni : 6] = (
            -np.where(counted, cap, 0.0),
            np.where(counted, cap, 0.0),
        )
    for comp, cap in ((3, R * lever[:, 0]), (4, R * lever[:, 1])):  # Eq. 9
        lo[comp : 6 * ni : 6], hi[comp : 6 * ni : 6] = -cap, cap
    max_lambda = np.zeros(n_col)
    max_lambda[-1] = -1.0
    h = _highs(max_lambda, lo, hi, A_eq, b_eq)

    def solve(phase):
        h.run()
        check_interrupt()  # a SIGINT/SIGTERM that arrived while HiGHS ran
        ms = h.getModelStatus()
        if ms == highspy.HighsModelStatus.kUnbounded:
            raise LimitAnalysisError(
                "the limit analysis is unbounded: the restraints leave no mechanism"
            )
        if ms == highspy.HighsModelStatus.kInfeasible and not history:
            raise LimitAnalysisError(
                "the dead load alone has no equilibrium inside the joint strengths"
            )
        if ms != highspy.HighsModelStatus.kOptimal:
            raise _Stop(
                f"the {phase} LP stopped at round {len(history) + 1}: {h.modelStatusToString(ms)}"
            )
        return np.asarray(h.getSolution().col_value)

    history, cuts, status, converged, excess = [], 0, "", False, np.inf
    n_eq, cut_ub = A_eq.shape[0], np.zeros(0)
    f = np.asarray(caps_at, dtype=float)
    try:
        for _ in range(max_rounds):
            x = solve("collapse")
            lam = float(x[-1])
            history.append(lam)
            f = x[:-1].reshape(ni, 6)
            ex, u, v = domain_excess(f, F, M, alpha)
            excess = float(ex[counted].max(initial=0.0))
            if excess <= domain_tolerance:
                converged, status = True, "converged"
                break
            # settled: two rounds in a row within the tolerance (one alone can be a pause while
            # other joints are cut: S23 keeps lambda for a round, then drops 2.5 %)
            if len(history) > 2 and max(
                abs(lam - history[-2]), abs(lam - history[-3])
            ) <= lambda_tolerance * abs(lam):
                converged = True
                status = f"lambda settled (domain excess {excess:.1e} left)"
                break
            if cut_ub.size:
                # planes the centre solution stays well inside of: dropped (re-cut if needed)
                row = np.asarray(h.getSolution().row_value)[n_eq:]
                slack = cut_ub - row
                drop = np.flatnonzero(slack > DROP * np.maximum(np.abs(cut_ub), 1e-300))
                if drop.size:
                    h.deleteRows(drop.size, (drop + n_eq).astype(np.int32))
                    cut_ub = np.delete(cut_ub, drop)
            which = np.flatnonzero(counted & (ex > domain_tolerance))
            planes = [supporting_planes(f, F, c_T, u, v, alpha, which, turn) for turn in TURNS]
            cols, vals, ub = (np.concatenate(p) for p in zip(*planes))
            which = np.concatenate([which] * len(TURNS))
            keep = vals != 0.0
            counts = keep.sum(axis=1)
            starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
            added = h.addRows(
                which.size,
                np.full(which.size, -np.inf),
                ub,
                int(counts.sum()),
                starts.astype(np.int32),
                cols[keep].astype(np.int32),
                vals[keep],
            )
            if added != highspy.HighsStatus.kOk:
                raise _Stop(f"HiGHS refused the planes of round {len(history)}")
            cuts += which.size
            cut_ub = np.concatenate([cut_ub, ub])
        else:
            status = f"not settled in {max_rounds} rounds (domain excess {excess:.1e})"
    except _Stop as stop:
        status = str(stop)
    lam = history[-1] if history else float("nan")
    return LimitAnalysisResult(
        lam,
        converged,
        status,
        len(history),
        cuts,
        excess,
        time.perf_counter() - t0,
        f,
        np.asarray(history),
    )


class _Stop(Exception):
    pass
