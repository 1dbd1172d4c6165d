"""Point contacts at the vertices (``contact.model: point``, the default): UDEC-style.

The force is carried by the two end points of the contact face, as in UDEC/3DEC's
vertex-edge contacts (Cundall 1971; Itasca UDEC theory, "contact stiffness per unit
length"); no overlap polygon is clipped:

- detection and reference face by separating axes (:func:`deepest_face`): the pair touches
  when no edge normal of either body separates them; the reference face is the edge, of
  either body, along whose normal they overlap least (a's unless b's is shallower by more
  than FACE_SWITCH_TOLERANCE, so a flush joint does not flip between its two faces); a
  touching pair keeps each body's edge of least overlap from step to step while the bodies
  have provably not moved and turned enough to change it (:func:`faces_hold`), and then
  measures just those two edges, with the same result bit for bit;
- the contact faces are that face and the other body's edge whose outward normal is most
  opposed to it; the frame's normal n is the bisector of the two faces' normals (a's
  outward and b's inward), so it is the same whichever face is the reference;
- their common extent along the tangent, [s_lo, s_hi], has at each end a vertex of one
  body facing the other body's face (where both bodies have a vertex at the same place,
  as for flush drums, the one whose face is the longer carries it);
- each end vertex that lies behind the other face by a depth d > 0 pushes along that
  face's normal with F = K d + c v_N (no tension), K = k_n L / 2, L = s_hi - s_lo the
  face contact length; a face-to-face contact thus has stiffness k_n L like the Winkler
  layer of the area law, but its resultant sits at the pivoting corner whatever k_n is, so
  a rocking block turns about its true corner and uplift starts at the rigid limit
  (moment = W b / 2), not at the Winkler layer's b / 6;
- each end's dashpot is c = 2 zeta sqrt(K m), m the lighter free body of the pair
  (``contact.damping``), so the landing corner of a rocking block loses a
  stiffness-independent share of its energy at impact (calibrated to Housner,
  docs/method/engine.md);
- the stored energy is sum K d^2 / 2, conservative for a fixed face (a vertex-edge law).

Each end also has its own tangential spring (k_t / 2) and dashpot (c_t / 2) capped by
Coulomb mu F_N of that end (:func:`stonedem.kernels.contact.tangential_force`), as UDEC gives
each contact point a shear spring; one spring at a moving load point would not be
conservative. If both ends stand clear while the polygons still overlap (a corner against
a corner of another face, rare), the overlap polygon is clipped and the pair falls back to
the area law's k_n A at its centroid, so nothing can tunnel.

Clipping the overlap polygon and its frame was most of a contact-step's cost; the
separating-axis test and the kept faces are what is left (measured: docs/notebook.md,
"Measurements moved out of the code").
"""

import numpy as np
from numba import njit

from stonedem.kernels import INLINE_OPTIONS, NO_ALLOC_OPTIONS
from stonedem.kernels.contact import (
    E_BASE_WORK,
    E_DAMPING,
    E_TANGENTIAL,
    END_FT,
    END_SLOTS,
    MEM_ACTIVE,
    MEM_END,
    MEM_M_DAMP,
    push_pair,
    record_point_force,
    relative_velocity,
    release_contact,
    tangential_force,
)
from stonedem.kernels.overlap import clip_convex_polygons, polygon_area_centroid
from stonedem.kernels.scalar import sqrt

# an end counts as shared by both bodies' vertices when they lie this close along the
# tangent, relative to the contact length
SHARED_END_TOLERANCE = 1e-9
# b's face becomes the reference only if its overlap is shallower than a's by this much,
# relative to the bodies' size [1] (a flush joint's two faces overlap equally)
FACE_SWITCH_TOLERANCE = 1e-9

# Columns of Work.face_cache: a pair slot's separating-axis result, kept while the bodies have
# provably not moved enough to change it (:func:`faces_hold`), so a touching pair measures
# two edges a step instead of every edge of both bodies, with the same result bit for bit
FACE_A = 0  # a's edge of least overlap (counted from its first vertex); -1: nothing kept
FACE_B = 1  # b's
# by how much that edge's separation exceeded every other edge of a's, less FACE_SLACK [m]
GAP_A = 2
GAP_B = 3
POSE_AX = 4  # the two bodies' poses then [m], [rad]
POSE_AY = 5
POSE_AT = 6
POSE_BX = 7
POSE_BY = 8
POSE_BT = 9
REACH = 10  # |x_b - x_a| + |y_b - y_a| then [m]
N_FACE_CACHE = 11
# rounding allowance of a kept gap, relative to the coordinates' size: separations carry
# errors of a few units in the last place (~1e-16 relative), this is 10 000 times that
FACE_SLACK = 1e-12


@njit(**INLINE_OPTIONS)
def body_edge(s, n, k, world_x, world_y, edge_len, edge_nx, edge_ny):
    """Length [m] and outward unit normal of edge k -> k+1 of the body whose world vertices
    are s..s+n-1, into edge_*[s + k]; a zero-length edge has normal (0, 0)."""
    i = s + k
    i1 = i + 1 if k + 1 < n else s
    ex = world_x[i1] - world_x[i]
    ey = world_y[i1] - world_y[i]
    length = sqrt(ex * ex + ey * ey)
    edge_len[i] = length
    if length > 0.0:
        inv = 1.0 / length  # one division for both components
        edge_nx[i] = ey * inv
        edge_ny[i] = -ex * inv
    else:
        edge_nx[i] = 0.0
        edge_ny[i] = 0.0


@njit(**INLINE_OPTIONS)
def body_edges(s, n, world_x, world_y, edge_len, edge_nx, edge_ny):
    """:func:`body_edge` of every edge of the body whose world vertices are s..s+n-1."""
    for k in range(n):
        body_edge(s, n, k, world_x, world_y, edge_len, edge_nx, edge_ny)


@njit(**INLINE_OPTIONS)
def world_edges(n_body, vert_start, world_x, world_y, edge_len, edge_nx, edge_ny):
    """Every edge k -> k+1 of every body at this step (:func:`body_edges`).

    Once a step and body, not once per pair and direction: a column's drum has two pairs, each
    of which looked at both bodies' edges three times.
    """
    for b in range(n_body):
        body_edges(
            vert_start[b],
            vert_start[b + 1] - vert_start[b],
            world_x,
            world_y,
            edge_len,
            edge_nx,
            edge_ny,
        )


@njit(**INLINE_OPTIONS)
def edge_separation(world_x, world_y, edge_nx, edge_ny, i, sb, nb):
    """Signed distance [m] of polygon b's deepest vertex (sb..sb+nb-1 of the world arrays)
    along the outward normal of edge i -> i+1 of another polygon (:func:`world_edges`)."""
    nx = edge_nx[i]
    ny = edge_ny[i]
    ox = world_x[i]
    oy = world_y[i]
    deepest = np.inf
    for j in range(sb, sb + nb):
        d = (world_x[j] - ox) * nx + (world_y[j] - oy) * ny
        if d < deepest:
            deepest = d
    return deepest


@njit(**INLINE_OPTIONS)
def deepest_face(world_x, world_y, edge_len, edge_nx, edge_ny, sa, na, sb, nb):
    """(separation [m], edge k, next separation [m]) of polygon b from the edges of the
    counter-clockwise polygon a.

    a is vertices sa..sa+na-1 of the world arrays, b vertices sb..sb+nb-1 (offsets into
    them, so a pair builds no slice views); edge_len, edge_nx, edge_ny: length and outward
    unit normal of each edge k -> k+1 (:func:`world_edges`).
    For each of a's edges, :func:`edge_separation`; returned for the edge where that is
    largest (the first of equals), k counted from sa, with the largest over a's other edges.
    The separation is >= 0 when that edge separates the polygons (returned at once, the
    next separation then -inf), else minus the overlap depth.
    """
    best = -np.inf
    best_k = 0
    second = -np.inf
    for k in range(na):
        i = sa + k
        if edge_len[i] <= 0.0:
            continue
        deepest = edge_separation(world_x, world_y, edge_nx, edge_ny, i, sb, nb)
        if deepest >= 0.0:
            return deepest, k, -np.inf
        if deepest > best:
            second = best
            best = deepest
            best_k = k
        elif deepest > second:
            second = deepest
    return best, best_k, second


@njit(**INLINE_OPTIONS)
def faces_hold(cache, p, a, b, body_x, body_y, body_theta, body_radius):
    """True when pair slot p's kept faces are still each body's edge of least overlap.

    A separation (w - o) . n of b's vertex w from a's edge (origin o, normal n) is, in a's
    frame, R(-theta_a) (x_b - x_a) . nu + R(theta_b - theta_a) l . nu + const, so moving the
    bodies by D (sum of |dx| + |dy|) and turning them by A and B changes it by at most
    D + REACH A + r_b (A + B); every edge's separation, the largest included, moves that
    little, so the kept edge stays the largest while twice it is below the kept gap.
    """
    ta = body_theta[a]
    tb = body_theta[b]
    move = (
        abs(body_x[a] - cache[p, POSE_AX])
        + abs(body_y[a] - cache[p, POSE_AY])
        + abs(body_x[b] - cache[p, POSE_BX])
        + abs(body_y[b] - cache[p, POSE_BY])
    )
    turn_a = abs(ta - cache[p, POSE_AT])
    turn_b = abs(tb - cache[p, POSE_BT])
    reach = cache[p, REACH]
    both = turn_a + turn_b
    return (
        2.0 * (move + reach * turn_a + body_radius[b] * both) < cache[p, GAP_A]
        and 2.0 * (move + reach * turn_b + body_radius[a] * both) < cache[p, GAP_B]
    )


@njit(**INLINE_OPTIONS)
def keep_faces(
    cache, p, a, b, face_a, face_b, gap_a, gap_b, body_x, body_y, body_theta, body_radius
):
    """Keep pair slot p's faces and gaps (separation less the next one, per body) [m] with
    the poses they hold for, less a rounding allowance; nothing when a gap is not positive
    (the caller empties the slot, FACE_A = -1, before the full test that calls this)."""
    xa = body_x[a]
    ya = body_y[a]
    xb = body_x[b]
    yb = body_y[b]
    reach = abs(xb - xa) + abs(yb - ya)
    slack = FACE_SLACK * (
        abs(xa) + abs(ya) + abs(xb) + abs(yb) + reach + body_radius[a] + body_radius[b] + 1.0
    )
    if gap_a - slack <= 0.0 or gap_b - slack <= 0.0:
        return  # the caller left the slot empty
    cache[p, FACE_A] = face_a
    cache[p, FACE_B] = face_b
    cache[p, GAP_A] = gap_a - slack
    cache[p, GAP_B] = gap_b - slack
    cache[p, POSE_AX] = xa
    cache[p, POSE_AY] = ya
    cache[p, POSE_AT] = body_theta[a]
    cache[p, POSE_BX] = xb
    cache[p, POSE_BY] = yb
    cache[p, POSE_BT] = body_theta[b]
    cache[p, REACH] = reach


@njit(**INLINE_OPTIONS)
def contact_face(edge_len, edge_nx, edge_ny, s, n, dir_x, dir_y):
    """Index k (from s) of the edge k -> k+1 of the counter-clockwise polygon of vertices
    s..s+n-1 whose outward normal is closest to (dir_x, dir_y), and that edge's length [m]
    (lengths and unit normals: :func:`world_edges`)."""
    best = -np.inf
    best_k = 0
    best_len = 0.0
    for k in range(n):
        length = edge_len[s + k]
        if length <= 0.0:
            continue
        score = edge_nx[s + k] * dir_x + edge_ny[s + k] * dir_y
        if score > best:
            best = score
            best_k = k
            best_len = length
    return best_k, best_len


@njit(**INLINE_OPTIONS)
def release_end(mem, slot, k_end_t, energy_acc):
    """An end that no longer touches: forget it; its tangential spring's energy is lost."""
    energy_acc[E_TANGENTIAL] += 0.5 * mem[slot + END_FT] ** 2 / k_end_t
    mem[slot] = 0.0
    mem[slot + 2] = 0.0
    mem[slot + END_FT] = 0.0


@njit(**NO_ALLOC_OPTIONS)
def kinetic_energy(b, body_mass, body_inertia, body_driven, body_vx, body_vy, body_omega):
    """Kinetic energy of body b [J], 0 for a driven body."""
    if body_driven[b]:
        return 0.0
    return 0.5 * (
        body_mass[b] * (body_vx[b] ** 2 + body_vy[b] ** 2) + body_inertia[b] * body_omega[b] ** 2
    )


@njit(**NO_ALLOC_OPTIONS)
def plastic_impulse(
    a,
    b,
    px,
    py,
    nx,
    ny,
    mu,
    body_x,
    body_y,
    body_vx,
    body_vy,
    body_omega,
    body_mass,
    body_inertia,
    body_driven,
    energy_acc,
):
    """Housner's impact at a landing point p: stop its relative motion in one impulse.

    The impulse j on b (-j on a) at p brings b's velocity relative to a at p to rest
    (sticking) if that needs |j_t| <= mu j_n, else stops only its normal part with j on
    Coulomb's cone (sliding). It is Housner's assumption for a rocking block (1956, the
    landing corner does not bounce or slip; angular momentum about it is conserved), at
    any contact stiffness. The kinetic energy it removes is booked as normal dissipation,
    the work of a driven body's velocity as base work. Velocities are changed in place.
    """
    vnx = (
        body_vx[b]
        - body_omega[b] * (py - body_y[b])
        - body_vx[a]
        + body_omega[a] * (py - body_y[a])
    )
    vny = (
        body_vy[b]
        + body_omega[b] * (px - body_x[b])
        - body_vy[a]
        - body_omega[a] * (px - body_x[a])
    )
    u_n = vnx * nx + vny * ny
    if u_n >= 0.0:
        return  # separating already
    tx = ny
    ty = -nx
    u_t = vnx * tx + vny * ty
    # K: velocity change at p per unit impulse, summed over the free bodies
    k_xx = 0.0
    k_xy = 0.0
    k_yy = 0.0
    for body in (a, b):
        if body_driven[body]:
            continue
        rx = px - body_x[body]
        ry = py - body_y[body]
        inv_m = 1.0 / body_mass[body]
        inv_i = 1.0 / body_inertia[body]
        k_xx += inv_m + inv_i * ry * ry
        k_xy -= inv_i * rx * ry
        k_yy += inv_m + inv_i * rx * rx
    det = k_xx * k_yy - k_xy * k_xy
    if det <= 0.0:
        return
    # sticking: K j = -u
    jx = -(k_yy * vnx - k_xy * vny) / det
    jy = -(-k_xy * vnx + k_xx * vny) / det
    j_n = jx * nx + jy * ny
    j_t = jx * tx + jy * ty
    if j_n < 0.0 or abs(j_t) > mu * j_n:
        # sliding: j = j_n (n - sign(u_t) mu t), with the normal relative velocity stopped
        sgn = 1.0 if u_t > 0.0 else -1.0
        dx = nx - sgn * mu * tx
        dy = ny - sgn * mu * ty
        denom = nx * (k_xx * dx + k_xy * dy) + ny * (k_xy * dx + k_yy * dy)
        if denom <= 0.0:
            return
        j_n = -u_n / denom
        jx = j_n * dx
        jy = j_n * dy
    before = kinetic_energy(
        a, body_mass, body_inertia, body_driven, body_vx, body_vy, body_omega
    ) + kinetic_energy(b, body_mass, body_inertia, body_driven, body_vx, body_vy, body_omega)
    work = 0.0
    for body, sign in ((b, 1.0), (a, -1.0)):
        if body_driven[body]:
            # the driven body does work on the other through the impulse it gives it
            work -= sign * (jx * body_vx[body] + jy * body_vy[body])
            continue
        rx = px - body_x[body]
        ry = py - body_y[body]
        body_vx[body] += sign * jx / body_mass[body]
        body_vy[body] += sign * jy / body_mass[body]
        body_omega[body] += sign * (rx * jy - ry * jx) / body_inertia[body]
    after = kinetic_energy(
        a, body_mass, body_inertia, body_driven, body_vx, body_vy, body_omega
    ) + kinetic_energy(b, body_mass, body_inertia, body_driven, body_vx, body_vy, body_omega)
    energy_acc[E_BASE_WORK] += work
    energy_acc[E_DAMPING] += before - after + work


@njit(**INLINE_OPTIONS)
def face_contact_forces(model, state, work, a, b, ka, kb, dt, want_energy, stored):
    """The forces of touching pair (a, b) on its contact faces: a's edge ka and b's edge kb
    (counted from each body's first vertex; their lengths and normals in work.edge_*, the
    world vertices in work.world_*); returns ``stored`` plus the pair's stored elastic
    energy [J] (evaluated only when want_energy). The law of :func:`point_contact_forces`,
    which chooses the faces; a kernel that knows them (:mod:`stonedem.kernels.contact_graph`)
    calls this directly."""
    law = model.law
    k_n, k_t, c_t = law.k_n, law.k_t, law.c_t
    damping, impact = law.params[0], law.params[1] != 0.0  # zeta [1], a plastic landing
    vert_start, body_driven, body_mass, body_inertia = (
        model.vert_start,
        model.body_driven,
        model.body_mass,
        model.body_inertia,
    )
    body_x, body_y = state.body_x, state.body_y
    body_vx, body_vy, body_omega = state.body_vx, state.body_vy, state.body_omega
    pair_memory, energy_acc = state.pair_memory, state.energy_acc
    world_x, world_y = work.world_x, work.world_y
    edge_len, edge_nx, edge_ny = work.edge_len, work.edge_nx, work.edge_ny
    force_x, force_y, torque = work.force_x, work.force_y, work.torque
    base_force_x, base_force_y, scratch = work.base_force_x, work.base_force_y, work.scratch
    out_x = scratch[0]
    out_y = scratch[1]
    sa = vert_start[a]
    na = vert_start[a + 1] - sa
    sb = vert_start[b]
    nb = vert_start[b + 1] - sb
    len_a = edge_len[sa + ka]
    len_b = edge_len[sb + kb]
    mu = model.pair_mu[a, b]
    ka1 = ka + 1 if ka + 1 < na else 0
    kb1 = kb + 1 if kb + 1 < nb else 0
    # outward unit normals of the two faces
    fa_nx = edge_nx[sa + ka]
    fa_ny = edge_ny[sa + ka]
    fb_nx = edge_nx[sb + kb]
    fb_ny = edge_ny[sb + kb]
    # the frame: n from a to b, the bisector of a's outward and b's inward face normal
    nx = fa_nx - fb_nx
    ny = fa_ny - fb_ny
    norm = sqrt(nx * nx + ny * ny)
    if norm > 0.0:
        inv = 1.0 / norm  # one division for both components
        nx *= inv
        ny *= inv
    else:
        nx = fa_nx
        ny = fa_ny
    tx = ny
    ty = -nx
    # the faces' end vertices along the tangent, low end first
    sa0 = world_x[sa + ka] * tx + world_y[sa + ka] * ty
    sa1 = world_x[sa + ka1] * tx + world_y[sa + ka1] * ty
    sb0 = world_x[sb + kb] * tx + world_y[sb + kb] * ty
    sb1 = world_x[sb + kb1] * tx + world_y[sb + kb1] * ty
    ia_lo, ia_hi = (ka, ka1) if sa0 <= sa1 else (ka1, ka)
    ib_lo, ib_hi = (kb, kb1) if sb0 <= sb1 else (kb1, kb)
    sa_lo = min(sa0, sa1)
    sa_hi = max(sa0, sa1)
    sb_lo = min(sb0, sb1)
    sb_hi = max(sb0, sb1)
    length = min(sa_hi, sb_hi) - max(sa_lo, sb_lo)
    tol = SHARED_END_TOLERANCE * (len_a + len_b)
    # each end: the vertex that lies inside the other face's extent (the longer face
    # keeps a shared end, so flush drums use the upper drum's corners consistently)
    mem = pair_memory[a, b]
    n_end = 0
    stiffness = 0.5 * k_n * max(length, 0.0)
    k_end_t = 0.5 * k_t  # each end's tangential spring and dashpot: half the contact's
    c_end_t = 0.5 * c_t
    mass = (
        body_mass[a]
        if body_driven[b]
        else (body_mass[b] if body_driven[a] else min(body_mass[a], body_mass[b]))
    )
    c_end = 2.0 * damping * sqrt(stiffness * mass)  # each end's dashpot, zeta of critical
    for end in range(2):
        if length <= 0.0:
            release_end(mem, MEM_END + end * END_SLOTS, k_end_t, energy_acc)
            continue
        if end == 0:
            use_a = sa_lo > sb_lo + tol or (abs(sa_lo - sb_lo) <= tol and len_a < len_b)
            ia = ia_lo
            ib = ib_lo
        else:
            use_a = sa_hi < sb_hi - tol or (abs(sa_hi - sb_hi) <= tol and len_a < len_b)
            ia = ia_hi
            ib = ib_hi
        if use_a:
            # a's vertex behind b's face: pushes b along -(b's outward normal)
            px = world_x[sa + ia]
            py = world_y[sa + ia]
            enx = -fb_nx
            eny = -fb_ny
            depth = (px - world_x[sb + kb]) * enx + (py - world_y[sb + kb]) * eny
            vertex = float(ia + 1)
        else:
            px = world_x[sb + ib]
            py = world_y[sb + ib]
            enx = fa_nx
            eny = fa_ny
            depth = -((px - world_x[sa + ka]) * enx + (py - world_y[sa + ka]) * eny)
            vertex = -float(ib + 1)
        slot = MEM_END + end * END_SLOTS
        touched = mem[slot] != 0.0 and mem[slot + 1] == vertex
        if depth <= 0.0:
            release_end(mem, slot, k_end_t, energy_acc)
            continue
        if touched:
            offset = min(mem[slot + 2], depth)
        else:
            offset = 0.0
            if impact and mem[slot] == 0.0:
                offset = depth
                plastic_impulse(
                    a,
                    b,
                    px,
                    py,
                    enx,
                    eny,
                    mu,
                    body_x,
                    body_y,
                    body_vx,
                    body_vy,
                    body_omega,
                    body_mass,
                    body_inertia,
                    body_driven,
                    energy_acc,
                )
        mem[slot] = 1.0
        mem[slot + 1] = vertex
        mem[slot + 2] = offset
        depth -= offset
        v_n, v_t = relative_velocity(
            body_x, body_y, body_vx, body_vy, body_omega, a, b, px, py, enx, eny, eny, -enx
        )
        # thesis Eq. 3.4 at the point: spring + dashpot, no tension
        f_el = stiffness * depth
        f_damp = c_end * v_n
        if f_el + f_damp < 0.0:
            f_damp = -f_el
        f_end = f_el + f_damp
        # thesis Eq. 3.5-3.6 at the point, with its own spring (UDEC: one shear spring per
        # contact point), so the tangential law stays conservative as the load moves
        f_t, ft_el = tangential_force(
            mem[slot + END_FT], mu, f_end, v_t, k_end_t, c_end_t, dt, energy_acc
        )
        mem[slot + END_FT] = ft_el
        record_point_force(mem, n_end, px, py, enx, eny, f_damp, f_t)
        n_end += 1
        # force on b: f_end n - F_T t with t = n turned clockwise
        push_pair(
            a,
            b,
            body_x,
            body_y,
            body_driven,
            px,
            py,
            f_end * enx - f_t * eny,
            f_end * eny + f_t * enx,
            force_x,
            force_y,
            torque,
            base_force_x,
            base_force_y,
        )
        if want_energy:
            stored += 0.5 * stiffness * depth * depth + 0.5 * ft_el * ft_el / k_end_t
    if n_end == 0:
        # both ends clear while the polygons overlap: the area law's k_n A at the
        # centroid, without friction, so nothing tunnels
        n_over = clip_convex_polygons(
            world_x[sa : sa + na],
            world_y[sa : sa + na],
            world_x[sb : sb + nb],
            world_y[sb : sb + nb],
            out_x,
            out_y,
            scratch[2],
            scratch[3],
        )
        if n_over >= 3:
            area, cx, cy = polygon_area_centroid(out_x, out_y, n_over)
            f_fallback = k_n * area
            push_pair(
                a,
                b,
                body_x,
                body_y,
                body_driven,
                cx,
                cy,
                f_fallback * nx,
                f_fallback * ny,
                force_x,
                force_y,
                torque,
                base_force_x,
                base_force_y,
            )
    for k in range(n_end, 2):
        record_point_force(mem, k, 0.0, 0.0, nx, ny, 0.0, 0.0)
    mem[MEM_ACTIVE] = 1.0
    mem[MEM_M_DAMP] = 0.0
    return stored


@njit(**INLINE_OPTIONS)
def point_contact_forces(model, state, work, n_pair, dt, want_energy):
    """Point contacts at the contact face's end vertices: add every candidate pair's forces.

    model, state, work: the time loop's bundles (:mod:`stonedem.kernels.step`); this reads the
    world vertices and bounds of work and its first n_pair candidate pairs, writes every
    body's edges (:func:`world_edges`), adds to work's force, torque and base-force
    accumulators and to state's contact memory and energy accumulators. The law
    (model.law): k_n, the normal stiffness per unit contact length [N m-2]; k_t, c_t, each
    contact's tangential spring [N m-1] and dashpot [N s m-1], half of each per end; params:
    the dashpot of each end as a fraction of critical, zeta [1], then the landing rule: if
    non-zero, an end that starts to touch lands plastically (:func:`plastic_impulse`) and the
    depth it reached within that step is forgiven (a plastic offset that only shrinks), so
    the landing neither bounces nor depends on dt. dt [s]: the time step.
    Returns (n_contact, stored elastic energy [J], evaluated only when want_energy).

    Inlined into the loop by Numba, so handing it the bundles costs nothing (a call would pass
    its 41 arguments every step). work.face_cache keeps each pair slot's
    separating axes between steps (:func:`keep_faces`, :func:`faces_hold`; a sweep forgets
    them); a bundle whose cache has fewer rows than n_pair keeps none.
    """
    k_t = model.law.k_t
    vert_start = model.vert_start
    body_x, body_y = state.body_x, state.body_y
    pair_ft, pair_memory, energy_acc = state.pair_ft, state.pair_memory, state.energy_acc
    world_x, world_y = work.world_x, work.world_y
    edge_len, edge_nx, edge_ny = work.edge_len, work.edge_nx, work.edge_ny
    lo_x, lo_y, hi_x, hi_y = work.lo_x, work.lo_y, work.hi_x, work.hi_y
    pair_a, pair_b, face_cache = work.pair_a, work.pair_b, work.face_cache
    body_theta, body_radius = state.body_theta, model.body_radius
    keep = face_cache.shape[0] >= n_pair  # a Work bundle with no face cache (a test's) keeps none
    world_edges(body_x.shape[0], vert_start, world_x, world_y, edge_len, edge_nx, edge_ny)
    n_contact = 0
    stored = 0.0
    for p in range(n_pair):
        a = pair_a[p]
        b = pair_b[p]
        if lo_x[a] > hi_x[b] or lo_x[b] > hi_x[a] or lo_y[a] > hi_y[b] or lo_y[b] > hi_y[a]:
            if pair_memory[a, b, MEM_ACTIVE] != 0.0:
                release_contact(a, b, pair_ft, pair_memory, k_t, energy_acc)
            continue
        sa = vert_start[a]
        na = vert_start[a + 1] - sa
        sb = vert_start[b]
        nb = vert_start[b + 1] - sb
        # narrow phase by separating axes: touching iff no edge normal separates the pair; the
        # edges of least overlap kept from an earlier step while they provably still are
        sep_b = 0.0
        ref_b = 0
        if (
            keep
            and face_cache[p, FACE_A] >= 0.0
            and faces_hold(face_cache, p, a, b, body_x, body_y, body_theta, body_radius)
        ):
            ref_a = int(face_cache[p, FACE_A])
            sep_a = edge_separation(world_x, world_y, edge_nx, edge_ny, sa + ref_a, sb, nb)
            if sep_a < 0.0:
                ref_b = int(face_cache[p, FACE_B])
                sep_b = edge_separation(world_x, world_y, edge_nx, edge_ny, sb + ref_b, sa, na)
        else:
            if keep:
                face_cache[p, FACE_A] = -1.0
            sep_a, ref_a, next_a = deepest_face(
                world_x, world_y, edge_len, edge_nx, edge_ny, sa, na, sb, nb
            )
            if sep_a < 0.0:
                sep_b, ref_b, next_b = deepest_face(
                    world_x, world_y, edge_len, edge_nx, edge_ny, sb, nb, sa, na
                )
                if keep and sep_b < 0.0:
                    keep_faces(
                        face_cache,
                        p,
                        a,
                        b,
                        ref_a,
                        ref_b,
                        sep_a - next_a,
                        sep_b - next_b,
                        body_x,
                        body_y,
                        body_theta,
                        body_radius,
                    )
        if sep_a >= 0.0 or sep_b >= 0.0:
            if pair_memory[a, b, MEM_ACTIVE] != 0.0:
                release_contact(a, b, pair_ft, pair_memory, k_t, energy_acc)
            continue
        n_contact += 1
        # contact faces: the reference face and the other body's edge most opposed to it
        size = max(
            max(hi_x[a] - lo_x[a], hi_y[a] - lo_y[a]), max(hi_x[b] - lo_x[b], hi_y[b] - lo_y[b])
        )
        if sep_b > sep_a + FACE_SWITCH_TOLERANCE * size:
            kb = ref_b
            ka, _ = contact_face(
                edge_len, edge_nx, edge_ny, sa, na, -edge_nx[sb + kb], -edge_ny[sb + kb]
            )
        else:
            ka = ref_a
            kb, _ = contact_face(
                edge_len, edge_nx, edge_ny, sb, nb, -edge_nx[sa + ka], -edge_ny[sa + ka]
            )
        stored = face_contact_forces(model, state, work, a, b, ka, kb, dt, want_energy, stored)
    return n_contact, stored
