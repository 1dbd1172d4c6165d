"""Incremental-iterative pushover under generalized displacement control (manuscript 2.3).

F_ext = F_D + lambda F_L. The dead load is applied first (Newton, load control, damaged secant
stiffness of Eq. 13-14); then the load-weighted mean displacement g = c . q (c = F_L / |F_L|_1,
``work_control``; or one control DOF) grows step by step while lambda is an unknown (bordered
Newton: K dq = lambda-term - R with c . dq prescribed), so the path passes the peak whatever
part of the panel forms the mechanism. The iteration matrix is H^T D H with D the consistent
6 x 6 derivative of each interface's return map (forward differences, ``consistent``), plus
``residual_stiffness`` x K-bar on yielded components; sparse LU, kept across iterations while
it still cuts the residual ``reuse_ratio``-fold. Each step starts from the last converged
increment, scaled (``extrapolate``); a step that does not converge in ``max_iterations`` or
whose residual cycles between two active sets is halved. The run ends on the plateau of the
lambda-displacement curve (the limit load of the small-displacement model) or at a control
displacement of ``max_displacement`` (default: the wall thickness s).
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.linalg import lapack
from threadpoolctl import threadpool_limits

from stonedem.entry import check_interrupt, interruptible
from stonedem.wall.compatibility import panel_compatibility
from stonedem.wall.constitutive import JointStrength, return_map, return_map_derivative
from stonedem.wall.panel import Panel
from stonedem.wall.settings import SolverSettings  # noqa: F401 - the solver's settings, re-exported
from stonedem.wall.stiffness import local_stiffness, sections, to_global_order, to_local_order


@dataclass
class WallModel:
    """Everything the solver needs: geometry, compatibility, stiffness, strength, loads."""

    panel: Panel
    k_n: np.ndarray
    k_t: np.ndarray
    strength: JointStrength
    dead_load: np.ndarray  # (6 nb,) F_D
    live_load: np.ndarray  # (6 nb,) F_L
    fixed: np.ndarray  # (6 nb,) bool: pinned DOF (block centre) under the live load
    fixed_dead: np.ndarray = None  # (6 nb,) bool: pinned while the dead load is applied
    lines: list = field(default_factory=list)  # LineRestraint: straight restraint lines
    H: sp.csr_matrix = field(init=False)

    def __post_init__(self):
        self.H = panel_compatibility(self.panel)
        self.sec = sections(self.panel)
        self.k_local = local_stiffness(self.sec, self.k_n, self.k_t)
        if self.fixed_dead is None:
            self.fixed_dead = self.fixed
        self.forces_old = None
        self.use("dead")
        self.T_dead = self.T
        self.use("live")

    def use(self, phase):
        """The restraints of a phase ("dead": while the self-weight is applied, "live"): the
        reduction q = q0 + T v (``stonedem.wall.restraints``) and H T."""
        from stonedem.wall.restraints import reduction_matrix, restrained_dofs

        if phase == "dead":
            T = reduction_matrix(
                self.panel, self.fixed_dead, [ln for ln in self.lines if ln.dead_load]
            )
        else:
            T = getattr(self, "T_live", None)
            if T is None:
                T = self.T_live = reduction_matrix(self.panel, self.fixed, self.lines)
        self.T = T.tocsr()
        self.TT = self.T.T.tocsr()
        self.restrained = restrained_dofs(self.T)
        self.Hf = (self.H @ self.T).tocsr()

    def accept(self, rm):
        """The converged state the next step starts from (a released bending component keeps
        its moment from here: ``JointStrength.release_both_rotations``)."""
        self.forces_old = rm.forces.copy()

    def reduce(self, v):
        """A load (or weight) vector on the block DOFs -> the reduced coordinates: T^T v."""
        return self.TT @ v

    def expand(self, dv):
        """A reduced increment -> block DOFs: T dv."""
        return self.T @ dv

    def local_deformation(self, q):
        d = (self.H @ q).reshape(-1, 6)
        return to_local_order(d, self.sec.perm)

    def internal(self, q, plastic, cracked):
        """Internal forces on the reduced DOFs (T^T H^T f) for the block displacements ``q``."""
        rm = return_map(
            self.local_deformation(q),
            plastic,
            cracked,
            self.k_local,
            self.sec,
            self.strength,
            self.forces_old,
        )
        check_interrupt()  # a SIGINT/SIGTERM that arrived during the compiled call
        f_glob = to_global_order(rm.forces, self.sec.perm).ravel()
        return self.Hf.T @ f_glob, rm

    def tangent(self, rm, eps):
        factor = np.maximum(rm.tangent, eps)
        kd = to_global_order(self.k_local * factor, self.sec.perm).ravel()
        return (self.Hf.T @ sp.diags(kd) @ self.Hf).tocsc()

    def consistent_tangent(self, q, plastic, cracked, rm, eps):
        """H^T D H with D the 6 x 6 per-interface derivative of the return map (forward
        differences, vectorised over the interfaces) plus eps K-bar on yielded components."""
        d = self.local_deformation(q)
        ni = len(d)
        D = return_map_derivative(
            d, rm, plastic, cracked, self.k_local, self.sec, self.strength, eps, self.forces_old
        )
        check_interrupt()
        # local -> global component order
        P = self.sec.perm
        G = np.zeros_like(D)
        ii = np.arange(ni)[:, None, None]
        G[ii, P[:, :, None], P[:, None, :]] = D
        rows = (6 * np.arange(ni))[:, None, None] + np.arange(6)[None, :, None]
        cols = (6 * np.arange(ni))[:, None, None] + np.arange(6)[None, None, :]
        rows, cols = np.broadcast_arrays(rows, cols)
        Dg = sp.csr_matrix((G.ravel(), (rows.ravel(), cols.ravel())), shape=(6 * ni, 6 * ni))
        return (self.Hf.T @ Dg @ self.Hf).tocsc()


@dataclass
class PushoverResult:
    lam: np.ndarray  # (steps,)
    control: np.ndarray  # (steps,) control displacement [m]
    state: np.ndarray  # (steps, ni) damage state
    q: np.ndarray  # (steps, 6 nb) block displacements
    iterations: np.ndarray
    residual: np.ndarray
    control_dof: int
    lambda_max: float
    step_max: int
    status: str
    wall_seconds: float
    dead_state: np.ndarray
    interface_forces_at_max: np.ndarray
    settings: dict
    # False: the path ended before a limit (lambda_max is not a limit load)
    limit_reached: bool = True
    limit_note: str = ""  # why not, and what to raise
    # each plateau the path reached and the limit analysis on the caps at its peak (a plateau
    # more than ORACLE_TOLERANCE below it was a pause, not the limit: the path went on)
    plateau_checks: list = field(default_factory=list)


class PathRecord:
    """The converged steps of a pushover (both schemes) and its highest load so far."""

    def __init__(self, q, rm):
        self.lam, self.control, self.state = [0.0], [0.0], [rm.state.copy()]
        self.q, self.iterations, self.residual = [q.copy()], [0], [0.0]
        self.lam_max, self.step_max, self.forces_at_max = 0.0, 0, rm.forces.copy()
        self.proofs = []  # plateau_proof's notes, one per plateau the path reached

    def add(self, lam, u, q, rm, iterations, residual):
        self.lam.append(lam), self.control.append(u), self.state.append(rm.state.copy())
        self.q.append(q.copy()), self.iterations.append(iterations), self.residual.append(residual)
        if lam > self.lam_max:
            self.lam_max, self.step_max, self.forces_at_max = (
                lam,
                len(self.lam) - 1,
                rm.forces.copy(),
            )

    def result(self, control, status, t0, dead_state, settings) -> PushoverResult:
        reached, note = limit_verdict(status, np.array(self.lam), np.array(self.control), settings)
        return PushoverResult(
            np.array(self.lam),
            np.array(self.control),
            np.array(self.state),
            np.array(self.q),
            np.array(self.iterations),
            np.array(self.residual),
            int(control),
            float(self.lam_max),
            int(self.step_max),
            status,
            time.perf_counter() - t0,
            dead_state,
            self.forces_at_max,
            settings.as_dict(),
            reached,
            note,
            list(self.proofs),
        )


# a path stopped at solver.max_displacement counts as having reached its limit when lambda rose
# by less than this fraction over the last quarter of the push (the small-displacement limit is
# approached asymptotically: the manuscript cases rise 0.0-2.9 % there, an elastic path 33 %)
LEVEL_TOLERANCE = 0.05
# a path that stopped without converging has passed its limit when lambda fell this far below
# lambda_max after the peak
DROP_TOLERANCE = 0.05


def limit_verdict(status: str, lam: np.ndarray, control: np.ndarray, settings) -> tuple[bool, str]:
    """Whether a path ended at a limit load, and if not a note saying why and what to change.

    Limits: the plateau and drop stops, the secant scheme's limit load, a peak the limit
    analysis proves (``plateau_proof``) where the steps stopped converging past it, and a push
    to ``max_displacement`` on which lambda has levelled off. Not limits: ``max_steps``,
    ``max_seconds``, a push to ``max_displacement`` with lambda still rising, and a run that
    stopped converging before lambda fell after a peak.
    """
    lam_max = float(np.max(lam)) if len(lam) else 0.0
    if status.startswith(
        ("stopped: plateau", "stopped: lambda dropped", "stopped: peak proven", "limit load")
    ):
        return True, ""
    if len(lam) < 2 or lam_max <= 0.0:
        why = "no load step converged"
    elif status == "reached maximum control displacement":
        # lambda at 3/4 of the final control displacement (on its running maximum: monotone)
        u = np.maximum.accumulate(np.asarray(control, dtype=float))
        at = np.interp(0.75 * u[-1], u, lam) if u[-1] > 0 else lam[(3 * len(lam)) // 4]
        rise = lam_max / at - 1.0 if at > 0 else np.inf
        if rise <= LEVEL_TOLERANCE:
            return True, ""
        why = (
            f"lambda still rose {rise:.1%} over the last quarter of the push "
            f"(raise solver.max_displacement)"
        )
    elif status == "stopped: max_steps":
        why = f"the path stopped after solver.max_steps = {settings.max_steps} steps (raise it)"
    elif status == "stopped: max_seconds":
        why = f"the path stopped after solver.max_seconds = {settings.max_seconds:g} s (raise it)"
    else:
        if lam[-1] < (1.0 - DROP_TOLERANCE) * lam_max:
            return True, ""
        why = "the steps stopped converging before lambda fell after a peak"
    return False, f"no limit load reached: {why}; lambda_max is the highest load of the path so far"


def plateau_proof(model, path) -> tuple[bool, str]:
    """Whether the path's peak is the collapse load of the joint caps at that peak: the limit
    analysis on them (``stonedem.wall.limit_analysis``, an upper bound) lies within
    ``ORACLE_TOLERANCE`` above lambda_max. An LP with no answer proves nothing and refuses
    nothing (the plateau stands, as before this check)."""
    from stonedem.wall.limit_analysis import ORACLE_TOLERANCE, LimitAnalysisError, limit_multiplier

    try:
        la = limit_multiplier(model, caps_at=path.forces_at_max, lambda_tolerance=3e-3)
    except LimitAnalysisError as err:
        return True, f"lambda {path.lam_max:.6g}: no limit analysis ({err})"
    if not la.converged or not np.isfinite(la.lambda_limit):
        return True, f"lambda {path.lam_max:.6g}: no limit analysis ({la.status})"
    gap = la.lambda_limit / path.lam_max - 1.0 if path.lam_max > 0 else np.inf
    return gap <= ORACLE_TOLERANCE, (
        f"lambda {path.lam_max:.6g} at step {path.step_max}: limit analysis "
        f"on its caps {la.lambda_limit:.6g} ({gap:+.2%})"
    )


class ConvergenceError(RuntimeError):
    def __init__(self, message, state=None):
        super().__init__(message)
        self.state = state  # (q, lam, rm, iterations, residual) of the last iterate


class DeadLoadError(ConvergenceError):
    """The restraints leave a mechanism at lambda = 0: the self-weight cannot be carried."""


def _newton(
    model, q, plastic, cracked, lam, settings, ref, control=None, target=None, stagnation_ok=True
):
    """Residual iterations at fixed lambda (control None) or fixed control displacement.

    ``q`` is the full DOF vector; ``control`` a global DOF index. Returns q, lambda, the
    return map, iterations and the relative residual. ``stagnation_ok`` False: a chattering
    iterate below ``accept_tolerance`` is not kept (the caller cuts the step back instead).
    """
    F_D = model.reduce(model.dead_load)
    F_L = model.reduce(model.live_load)
    eps = settings.residual_stiffness
    q = q.copy()
    # the constraint c . q = target: a unit vector on one DOF, or a weight vector (full length)
    # cg on the block DOFs, cf = T^T cg on the reduced ones (c . T dv = cf . dv)
    if control is None:
        cg = cf = None
    else:
        if np.ndim(control) == 0:
            cg = np.zeros(model.dead_load.size)
            cg[int(control)] = 1.0
        else:
            cg = np.asarray(control, dtype=float)
        cf = model.reduce(cg)
    fint, rm = model.internal(q, plastic, cracked)
    R = F_D + lam * F_L - fint
    res = np.linalg.norm(R) / ref
    history = []
    refactor = True
    n_iter = settings.max_iterations if control is not None else settings.dead_load_iterations
    for it in range(1, n_iter + 1):
        history.append(res)
        # stagnation (active-set chattering) below the accept tolerance: keep this iterate
        if (
            stagnation_ok
            and it > 10
            and res < settings.accept_tolerance
            and cf is not None
            and min(history[-8:]) > 0.5 * history[-9]
        ):
            return q, lam, rm, it, res
        # a period-2 cycle between two active sets never converges: give up at once
        # (the caller halves the step) instead of spending the remaining iterations on it
        if (
            cf is not None
            and it >= 7
            and res >= settings.tolerance
            and abs(history[-1] - history[-3]) <= 0.02 * history[-1]
            and abs(history[-2] - history[-4]) <= 0.02 * history[-2]
        ):
            if stagnation_ok and res < settings.accept_tolerance:
                return q, lam, rm, it, res
            raise ConvergenceError(
                f"residual cycles between {history[-1]:.2e} and {history[-2]:.2e}",
                (q, lam, rm, it, res),
            )
        on_target = cf is None or abs(cg @ q - target) <= 1e-9 * max(abs(target), 1e-12)
        if res < settings.tolerance and on_target and it > 1:
            return q, lam, rm, it, res
        if refactor:
            if settings.consistent and cf is not None:  # load-controlled dead load: secant (robust)
                K = model.consistent_tangent(q, plastic, cracked, rm, eps)
            else:
                K = model.tangent(rm, eps if cf is not None else max(eps, 0.05))
            lu = _factor(K)
            if control is not None:
                dq_l = lu.solve(F_L)
        dq = lu.solve(R)
        dlam = 0.0
        if control is not None:
            cl = cf @ dq_l
            if abs(cl) < 1e-300:
                raise ConvergenceError(
                    "the controlled displacement does not respond to the live load"
                )
            # the constraint part of the step is kept whole; the residual part is line-searched
            dlam_c = (target - cg @ q) / cl
            dlam_r = -(cf @ dq) / cl
        # backtracking line search on the residual norm breaks contact/slip chattering
        best = None
        for step in (1.0, 0.5, 0.25, 0.125):
            qt = q.copy()
            if control is None:
                qt += model.expand(step * dq)
                lt = lam
            else:
                dlam = dlam_c + step * dlam_r
                qt += model.expand(step * dq + dlam * dq_l)
                lt = lam + dlam
            ft, rt = model.internal(qt, plastic, cracked)
            Rt = F_D + lt * F_L - ft
            rest = np.linalg.norm(Rt) / ref
            if best is None or rest < best[0]:
                best = (rest, qt, lt, rt, Rt)
            if rest < res:
                break
        # the factorization is kept while it still cuts the residual fast (modified Newton)
        refactor = best[0] > settings.reuse_ratio * res or step < 1.0
        res, q, lam, rm, R = best
        if not np.all(np.isfinite(q)):
            raise ConvergenceError("non-finite displacements")
    raise ConvergenceError(
        f"no convergence in {n_iter} iterations (residual {res:.2e})", (q, lam, rm, n_iter, res)
    )


class BandLU:
    """LU with partial pivoting of a banded matrix (LAPACK dgbtrf / dgbtrs), with splu's
    ``solve``."""

    def __init__(self, K, lower, upper):
        coo = K.tocoo()
        n = K.shape[0]
        band = np.zeros((2 * lower + upper + 1, n), order="F")  # LAPACK band storage
        band[lower + upper + coo.row - coo.col, coo.col] = coo.data
        self.lu, self.pivots, info = lapack.dgbtrf(band, lower, upper, overwrite_ab=1)
        if info > 0:
            raise RuntimeError(f"Factor is exactly singular (pivot {info})")
        self.lower, self.upper = lower, upper

    def solve(self, b):
        x, info = lapack.dgbtrs(self.lu, self.lower, self.upper, b, self.pivots)
        return x


def _factor(K, state=None):
    """LU of K; a singular or non-finite matrix is a ConvergenceError, not a crash.

    A wall's DOFs are numbered course by course, so K is banded (half-bandwidth 26-95 on the
    table walls), where a dense-band LU beats SuperLU (docs/notebook.md, "Measurements moved
    out of the code"). A matrix whose band is wider than a quarter of its size goes to SuperLU.
    """
    if not np.all(np.isfinite(K.data)):
        raise ConvergenceError("non-finite stiffness matrix", state)
    coo = K.tocoo()
    offsets = coo.row - coo.col
    lower, upper = int(offsets.max(initial=0)), int(-offsets.min(initial=0))
    try:
        banded = K.shape[0] > 0 and lower + upper <= K.shape[0] // 4
        lu = BandLU(coo, lower, upper) if banded else spla.splu(K.tocsc())  # coo.tocoo() is itself
    except RuntimeError as err:  # "Factor is exactly singular"
        raise ConvergenceError(f"singular stiffness matrix ({err})", state) from err
    check_interrupt()
    return lu


def choose_control_dof(model, q, plastic, cracked, settings):
    """The free DOF moving most under the live load, in the state after the dead load."""
    _, rm = model.internal(q, plastic, cracked)
    K = model.tangent(rm, settings.residual_stiffness)
    q_l = model.expand(_factor(K).solve(model.reduce(model.live_load)))
    if not np.all(np.isfinite(q_l)):
        raise ConvergenceError("the live load gives non-finite displacements")
    direction = np.flatnonzero(model.live_load != 0)
    comp = direction[0] % 6 if len(direction) else 2
    dofs = np.arange(q_l.size)
    cand = np.flatnonzero(((dofs % 6) == comp) & ~model.restrained)
    if not len(cand):
        raise ConvergenceError("the live load acts only on restrained DOFs")
    c = cand[np.argmax(np.abs(q_l[cand]))]
    if q_l[c] == 0.0:
        raise ConvergenceError("the live load moves no free DOF in its direction")
    return int(c), float(q_l[c])


def _apply_dead_load(model, settings, ref):
    """Self-weight at lambda = 0 under load control with the restraints that carry it, then the
    remaining restraints hold the blocks where the dead load left them."""
    ni = model.panel.n_interfaces
    model.forces_old = None
    q = np.zeros(model.dead_load.size)
    plastic = np.zeros((ni, 6))
    cracked = np.zeros(ni, dtype=bool)
    try:
        model.use("dead")
        q, _, rm, _, _ = _newton(model, q, plastic, cracked, 0.0, settings, ref)
        plastic, cracked = rm.plastic, rm.cracked
        model.accept(rm)
        dead_state = rm.state.copy()
        model.use("live")
        q, _, rm, _, _ = _newton(model, q, plastic, cracked, 0.0, settings, ref)
        model.accept(rm)
    except (ConvergenceError, RuntimeError) as err:  # splu: "Factor is exactly singular"
        raise DeadLoadError(f"the self-weight cannot be carried ({err})") from err
    return q, rm, dead_state


def dead_load_state(model, settings=None):
    """Interface actions (ni, 6) after the pushover's own dead-load stage: the caps of a limit
    analysis of the dead-loaded wall (``stonedem.wall.limit_analysis.limit_multiplier``)."""
    settings = settings or SolverSettings()
    ref = np.linalg.norm(model.dead_load) + np.linalg.norm(model.live_load)
    _, rm, _ = _apply_dead_load(model, settings, ref)
    model.use("live")
    return rm.forces.copy()


def _secant_step(model, q, plastic, cracked, K_lu, lam, settings, ref):
    """Residual iterations at load ``lam`` with a fixed (previous-step secant) matrix.

    Returns q, return map, iterations, relative residual; raises ConvergenceError.
    """
    F = model.reduce(model.dead_load + lam * model.live_load)
    q = q.copy()
    fint, rm = model.internal(q, plastic, cracked)
    R = F - fint
    res = np.linalg.norm(R) / ref
    refresh = int(settings.secant_refresh)
    for it in range(1, settings.max_iterations + 1):
        if refresh and it > 1 and (it - 1) % refresh == 0:
            K_lu = _factor(model.tangent(rm, settings.residual_stiffness))
        dq = K_lu.solve(R)
        if not np.all(np.isfinite(dq)):
            raise ConvergenceError("singular stiffness matrix")
        q += model.expand(dq)
        fint, rm = model.internal(q, plastic, cracked)
        R = F - fint
        res = np.linalg.norm(R) / ref
        if res < settings.tolerance:
            return q, rm, it, res
    raise ConvergenceError(
        f"no convergence in {settings.max_iterations} iterations (residual {res:.2e})",
        (q, lam, rm, settings.max_iterations, res),
    )


def _dead_load_and_control(model, settings, control_block):
    """The start both schemes share: the dead-load state, and the control DOF with its unit
    displacement (``control_block``: that block's DOF in the chosen direction)."""
    ref = np.linalg.norm(model.dead_load) + np.linalg.norm(model.live_load)
    q, rm, dead_state = _apply_dead_load(model, settings, ref)
    control, unit = choose_control_dof(model, q, rm.plastic, rm.cracked, settings)
    if control_block is not None:
        control = 6 * int(control_block) + int(control % 6)
        if model.restrained[control]:
            raise ConvergenceError(f"control block {control_block} is restrained")
    return ref, q, rm, dead_state, control, unit


def one_blas_thread(solver):
    """Run ``solver`` with BLAS on one thread: the banded LU (dgbtrf) is too small to gain from
    more, and OpenBLAS's spinning threads made two wall jobs side by side 4-40x slower."""

    @functools.wraps(solver)
    def wrapper(*args, **kwargs):
        with threadpool_limits(limits=1, user_api="blas"):
            return solver(*args, **kwargs)

    return wrapper


@interruptible
@one_blas_thread
def secant_pushover(
    model: WallModel, settings: SolverSettings | None = None, control_block=None, progress=None
) -> PushoverResult:
    """Manuscript 2.3: load increments dF = d(lambda) F_L; the panel stiffness of step i is
    H^T K-bar(damage of step i-1) H (Eq. 13-14: yielded components at zero, plus
    ``residual_stiffness`` x K-bar so that the LU exists); residual iterations with that
    matrix at fixed load. The limit load is the last converged load when the increment has
    been halved down to ``min_load_step`` x the first one, or when the incremental
    flexibility (load-weighted mean displacement per unit lambda) exceeds ``singular_ratio``
    x the initial one (the stiffness matrix is singular: the displacement grows unboundedly).
    """
    settings = settings or SolverSettings()
    t0 = time.perf_counter()
    ref, q, rm, dead_state, control, unit = _dead_load_and_control(model, settings, control_block)
    if progress:
        progress(0, 0.0, 0.0)  # the dead load is on (a slow one shows in the log)
    plastic, cracked = rm.plastic, rm.cracked
    sign = 1.0 if unit >= 0 else -1.0
    w = np.where(model.restrained, 0.0, model.live_load)
    cvec = w / np.abs(w).sum()
    eps = settings.residual_stiffness
    K_lu = _factor(model.tangent(rm, eps))
    flex0 = abs(cvec @ model.expand(K_lu.solve(model.reduce(model.live_load))))
    # first increment: 1/50 of the overturning load of the free-standing wall (lambda = s/H for
    # a load proportional to the weight), unless the case gives one
    weight = -model.dead_load[1::6].sum()
    dlam0 = settings.load_step or (
        float(model.panel.block["s"])
        / model.panel.height
        * weight
        / max(np.abs(model.live_load).sum(), 1e-300)
        / 50.0
    )
    dlam = dlam0
    u0 = q[control]
    lam = 0.0
    path = PathRecord(q, rm)
    status = "stopped: max_steps"
    steps = 0
    while steps < settings.max_steps:
        if settings.max_seconds and time.perf_counter() - t0 > settings.max_seconds:
            status = "stopped: max_seconds"
            break
        g_prev = cvec @ q
        try:
            q_new, rm_new, it, res = _secant_step(
                model, q, plastic, cracked, K_lu, lam + dlam, settings, ref
            )
            flex = abs(cvec @ q_new - g_prev) / dlam
            if flex > settings.singular_ratio * flex0:
                raise ConvergenceError("unbounded displacement")
        except ConvergenceError as err:
            if progress:
                progress(steps, lam + dlam, float("nan"), str(err))
            dlam *= 0.5
            if dlam < settings.min_load_step * dlam0:
                status = f"limit load: {err} at the smallest load increment"
                break
            continue
        steps += 1
        lam += dlam
        q, rm, plastic, cracked = q_new, rm_new, rm_new.plastic, rm_new.cracked
        model.accept(rm)
        path.add(lam, (q[control] - u0) * sign, q, rm, it, res)  # lambda only grows here
        if progress:
            progress(steps, lam, path.control[-1])
        # stiffness of the next step from the damage of this one (manuscript 2.3)
        try:
            K_lu = _factor(model.tangent(rm, eps))
        except ConvergenceError as err:  # a mechanism: the displacement grows unboundedly
            status = f"limit load: {err}"
            break
        if it <= max(settings.max_iterations // 10, 2):
            dlam = min(dlam * settings.growth, dlam0)
    return path.result(control, status, t0, dead_state, settings)


@interruptible
@one_blas_thread
def pushover(
    model: WallModel, settings: SolverSettings | None = None, control_block=None, progress=None
) -> PushoverResult:
    """Dead load, then displacement-controlled live load to the limit and beyond
    (``settings.secant``: the manuscript's load-controlled secant scheme instead).

    SIGINT/SIGTERM raise :class:`stonedem.entry.Interrupted` between compiled calls, never inside
    one (:func:`stonedem.entry.deferred_signals`)."""
    settings = settings or SolverSettings()
    if settings.secant:
        return secant_pushover(model, settings, control_block, progress)
    t0 = time.perf_counter()
    ref, q, rm, dead_state, control, unit = _dead_load_and_control(model, settings, control_block)
    if progress:
        progress(0, 0.0, 0.0)  # the dead load is on (a slow one shows in the log)
    plastic, cracked = rm.plastic, rm.cracked
    sign = 1.0 if unit >= 0 else -1.0
    s = float(model.panel.block["s"])
    # small-displacement limit analysis: lambda approaches its plateau asymptotically (S5: 3 %
    # below it at s/10, on it by s/2), so the path runs up to s unless the plateau stop ends it
    u_max = settings.max_displacement or s
    # the stepped quantity g = c . q: the load-weighted mean displacement (work control, passes
    # limit points whatever part of the panel forms the mechanism) or the control DOF
    cvec = np.zeros(model.dead_load.size)
    if settings.work_control:
        w = np.where(model.restrained, 0.0, model.live_load)
        cvec = w / np.abs(w).sum()
        _, rm0 = model.internal(q, plastic, cracked)
        q_l = _factor(model.tangent(rm0, settings.residual_stiffness)).solve(
            model.reduce(model.live_load)
        )
        ratio = abs(cvec @ model.expand(q_l)) / abs(unit)
    else:
        cvec[control] = sign
        ratio = 1.0
    du = settings.first_step or max(abs(unit) * 1e-3, u_max * 1e-7)
    last = None  # (dq, dlambda, dg) of the last converged step
    du *= ratio
    g_max = u_max * ratio
    du_min = 1e-9 * g_max
    failures = 0
    u0 = q[control]
    g0 = cvec @ q

    lam = 0.0
    path = PathRecord(q, rm)
    since_max, status = 0, "reached maximum control displacement"
    lam_rise, g_rise = 0.0, 0.0
    steps = 0
    while steps < settings.max_steps:
        if settings.max_seconds and time.perf_counter() - t0 > settings.max_seconds:
            status = "stopped: max_seconds"
            break
        target = cvec @ q + du
        # predictor: the last converged increment, scaled to this one (secant extrapolation)
        q_guess, lam_guess = q, lam
        if settings.extrapolate and last is not None:
            scale = du / last[2]
            q_guess, lam_guess = q + scale * last[0], lam + scale * last[1]
        err = None
        try:
            # a chattering iterate is kept only on the last attempt: cutting the step back
            # first avoids carrying a ~1e-3 residual into the next steps (S11 stalled on it)
            q_new, lam_new, rm, it, res = _newton(
                model,
                q_guess,
                plastic,
                cracked,
                lam_guess,
                settings,
                ref,
                cvec,
                target,
                stagnation_ok=failures >= settings.max_failures - 1,
            )
        except ConvergenceError as first:
            err = first
        if err is not None:
            if progress:
                progress(steps, lam, float("nan"), str(err))
            failures += 1
            # below a billionth of the push the path does not go on in g (it turns back past a
            # peak): halving further only underflowed du to 0 (0/0 in the predictor)
            if du <= du_min:
                status = "stopped: no convergence at the smallest step"
                break
            if failures < settings.max_failures:
                du = max(0.5 * du, du_min)
                continue
            # after repeated halving, accept a nearly converged iterate (its residual is recorded)
            if err.state is None or not err.state[4] < settings.accept_tolerance:
                status = "stopped: no convergence after repeated step halving"
                break
            q_new, lam_new, rm, it, res = err.state
        steps += 1
        failures = 0
        last = (q_new - q, lam_new - lam, du)
        q, lam, plastic, cracked = q_new, lam_new, rm.plastic, rm.cracked
        model.accept(rm)
        u = (q[control] - u0) * sign
        g = cvec @ q - g0
        path.add(lam, u, q, rm, it, res)
        # plateau: lambda has not risen by plateau_tolerance since the step at g_rise
        if lam > lam_rise * (1 + settings.plateau_tolerance):
            since_max, lam_rise, g_rise = 0, lam, g
        else:
            since_max += 1
        if progress:
            progress(steps, lam, u)
        if u >= u_max or g >= g_max:
            break
        if path.lam_max > 0 and lam < settings.drop_ratio * path.lam_max:
            status = "stopped: lambda dropped below drop_ratio x lambda_max"
            break
        if since_max >= settings.plateau_steps and g > 2 * g_rise:
            # a flat stretch can be a pause before the path stiffens again (the window wall of
            # tests/wall/test_openings_load_path.py: 1.4 % down and back, then 14 % higher):
            # it ends the run only where it is the collapse load of the caps at the peak
            proven, note = plateau_proof(model, path)
            path.proofs.append(note)
            if proven:
                status = "stopped: plateau (no increase of lambda)"
                break
            since_max, g_rise = 0, g
        if it <= settings.easy_iterations:
            du *= settings.growth
        du = min(du, g_max / 20)
    else:
        status = "stopped: max_steps"
    if status.startswith("stopped: no convergence") and path.lam_max > 0:
        # past a peak the path can turn back (a snap-back in g): that peak is still the limit
        # load where the limit analysis on its caps proves it
        proven, note = plateau_proof(model, path)
        path.proofs.append(note)
        if proven:
            status = f"stopped: peak proven by the limit analysis ({status[9:]} past it)"
    return path.result(control, status, t0, dead_state, settings)
