"""Narrow phase: overlap polygon of two convex polygons and its contact frame (thesis 3.6-3.7).

The overlap of two convex polygons is found by Sutherland-Hodgman clipping: the subject
polygon is clipped in turn by the half-plane left of every edge of the (counter-clockwise)
clip polygon. Its area and centroid follow thesis Eq. 3.1-3.3.

Two contact frames are offered (``FRAME_*``):

- FRAME_BOUNDARY (default): the normal is the direction in which moving b away from a
  shrinks the overlap fastest, i.e. the sum of (length x outward normal) over the overlap
  edges lying on a's boundary minus that over the edges on b's boundary (edges on both,
  such as the flush sides of aligned drums, cancel and are skipped). It equals the thesis'
  rule where that rule is unambiguous (a corner triangle: the longest side, on the face),
  follows the face of a thin sliver exactly, and changes smoothly as a triangle becomes a
  quadrilateral.
- FRAME_THESIS: thesis 3.7 as written: the tangent is parallel to the longest side of a
  triangular overlap, or to the longest line joining two non-consecutive vertices of a
  larger one. For a flat sliver L x d the two diagonals are equally long and tilt the
  normal by +-d/L, so a block resting flat feels a spurious sideways force of F_N d/L.
"""

from numba import njit

from stonedem.kernels import NO_ALLOC_OPTIONS
from stonedem.kernels.scalar import sqrt

MAX_OVERLAP_VERTICES = 64
FRAME_BOUNDARY = 0
FRAME_THESIS = 1
# vertices closer than this [m] are merged, so a vertex lying on an edge does not
# turn a triangle into a degenerate quadrilateral
DUPLICATE_VERTEX_TOLERANCE = 1e-12


@njit(**NO_ALLOC_OPTIONS)
def clip_convex_polygons(ax, ay, bx, by, out_x, out_y, tmp_x, tmp_y):
    """Clip convex polygon a by convex polygon b; return the vertex count written to out.

    ax, ay: vertices of a, counter-clockwise (n_a,) [m]
    bx, by: vertices of b, counter-clockwise (n_b,) [m]
    out_x, out_y, tmp_x, tmp_y: scratch of length >= n_a + n_b; the overlap polygon,
        counter-clockwise, is left in out_x[:n], out_y[:n]

    Pseudocode: poly <- a; for every edge (p, q) of b: keep the part of poly on the
    left of p->q (cross(q - p, v - p) >= 0), inserting the crossing points.
    """
    # ping-pong between the two buffers (src -> dst per clipping edge), no copies
    n = ax.shape[0]
    for i in range(n):
        tmp_x[i] = ax[i]
        tmp_y[i] = ay[i]
    src_x, src_y, dst_x, dst_y = tmp_x, tmp_y, out_x, out_y
    nb = bx.shape[0]
    for e in range(nb):
        px = bx[e]
        py = by[e]
        e1 = e + 1 if e + 1 < nb else 0
        ex = bx[e1] - px
        ey = by[e1] - py
        m = 0
        sx = src_x[0]
        sy = src_y[0]
        side_s = ex * (sy - py) - ey * (sx - px)
        for i in range(n):
            i1 = i + 1 if i + 1 < n else 0
            fx = src_x[i1]
            fy = src_y[i1]
            side_f = ex * (fy - py) - ey * (fx - px)
            if side_s >= 0.0:
                dst_x[m] = sx
                dst_y[m] = sy
                m += 1
            if (side_s >= 0.0) != (side_f >= 0.0):
                s = side_s / (side_s - side_f)
                dst_x[m] = sx + s * (fx - sx)
                dst_y[m] = sy + s * (fy - sy)
                m += 1
            sx = fx
            sy = fy
            side_s = side_f
        n = m
        if n < 3:
            return 0
        src_x, src_y, dst_x, dst_y = dst_x, dst_y, src_x, src_y
    if src_x is not out_x:
        for i in range(n):
            out_x[i] = src_x[i]
            out_y[i] = src_y[i]
    # merge duplicate consecutive vertices
    m = 0
    for i in range(n):
        if m > 0:
            dx = out_x[i] - out_x[m - 1]
            dy = out_y[i] - out_y[m - 1]
            if dx * dx + dy * dy <= DUPLICATE_VERTEX_TOLERANCE**2:
                continue
        out_x[m] = out_x[i]
        out_y[m] = out_y[i]
        m += 1
    while m > 1:
        dx = out_x[m - 1] - out_x[0]
        dy = out_y[m - 1] - out_y[0]
        if dx * dx + dy * dy <= DUPLICATE_VERTEX_TOLERANCE**2:
            m -= 1
        else:
            break
    if m < 3:
        return 0
    return m


@njit(**NO_ALLOC_OPTIONS)
def polygon_area_centroid(x, y, n):
    """Area [m2] and centroid [m] of the polygon x[:n], y[:n] (thesis Eq. 3.1-3.3).

    Coordinates are taken relative to the first vertex so slivers far from the origin
    keep their digits.
    """
    x0 = x[0]
    y0 = y[0]
    area2 = 0.0
    cx = 0.0
    cy = 0.0
    for i in range(n):
        xi = x[i] - x0
        yi = y[i] - y0
        i1 = i + 1 if i + 1 < n else 0
        xj = x[i1] - x0
        yj = y[i1] - y0
        cross = xi * yj - xj * yi
        area2 += cross
        cx += (xi + xj) * cross
        cy += (yi + yj) * cross
    if area2 <= 0.0:
        return 0.0, x0, y0
    return 0.5 * area2, x0 + cx / (3.0 * area2), y0 + cy / (3.0 * area2)


@njit(**NO_ALLOC_OPTIONS)
def contact_tangent(x, y, n):
    """Unit tangent (tx, ty) and its chord length [m] of the overlap polygon x[:n], y[:n].

    thesis 3.7: a triangle -> its longest side; a polygon with more vertices -> the longest
    line joining two non-consecutive vertices (for a quadrilateral, the longer diagonal).
    """
    best = -1.0
    bx = 1.0
    by = 0.0
    for i in range(n):
        for j in range(i + 1, n):
            if n > 3 and (j == i + 1 or (i == 0 and j == n - 1)):
                continue
            dx = x[j] - x[i]
            dy = y[j] - y[i]
            d2 = dx * dx + dy * dy
            if d2 > best:
                best = d2
                bx = dx
                by = dy
    length = sqrt(best)
    if length <= 0.0:
        return 1.0, 0.0, 0.0
    return bx / length, by / length, length


@njit(**NO_ALLOC_OPTIONS)
def on_boundary(px, py, vx, vy, tol):
    """True when point p lies on an edge of the polygon (vx, vy), within distance tol [m]."""
    n = vx.shape[0]
    for k in range(n):
        k1 = k + 1 if k + 1 < n else 0
        ex = vx[k1] - vx[k]
        ey = vy[k1] - vy[k]
        length = sqrt(ex * ex + ey * ey)
        if length <= 0.0:
            continue
        rx = px - vx[k]
        ry = py - vy[k]
        if abs(ex * ry - ey * rx) <= tol * length:
            along = (ex * rx + ey * ry) / length
            if -tol <= along <= length + tol:
                return True
    return False


@njit(**NO_ALLOC_OPTIONS)
def boundary_normal(x, y, n, ax, ay, bx, by, tol):
    """Unnormalised contact normal (from a to b) of the overlap polygon x[:n], y[:n].

    sum over overlap edges on a's boundary only of (length x outward normal), minus the
    same over edges on b's boundary only; the outward normal of a counter-clockwise edge
    (ex, ey) times its length is (ey, -ex).
    """
    dx = 0.0
    dy = 0.0
    for k in range(n):
        x0 = x[k]
        y0 = y[k]
        k1 = k + 1 if k + 1 < n else 0
        x1 = x[k1]
        y1 = y[k1]
        mx = 0.5 * (x0 + x1)
        my = 0.5 * (y0 + y1)
        on_a = on_boundary(mx, my, ax, ay, tol)
        on_b = on_boundary(mx, my, bx, by, tol)
        if on_a and not on_b:
            dx += y1 - y0
            dy -= x1 - x0
        elif on_b and not on_a:
            dx -= y1 - y0
            dy += x1 - x0
    return dx, dy


@njit(**NO_ALLOC_OPTIONS)
def contact_frame(x, y, n, ax, ay, bx, by, from_x, from_y, to_x, to_y, frame_rule):
    """Contact normal (nx, ny), tangent (tx, ty) and chord length of an overlap polygon.

    x, y: overlap polygon (n vertices); ax, ay, bx, by: the two bodies' vertices [m]
    from_*, to_*: centroids of bodies a and b, used to orient the thesis-rule normal
    frame_rule: FRAME_BOUNDARY or FRAME_THESIS (module docstring)
    The tangent is the normal turned clockwise by 90 degrees, so (t, n) is right-handed.
    """
    if frame_rule == FRAME_BOUNDARY:
        scale = 1.0 + abs(x[0]) + abs(y[0])
        dx, dy = boundary_normal(x, y, n, ax, ay, bx, by, 1e-9 * scale)
        norm = sqrt(dx * dx + dy * dy)
        if norm > 0.0:
            nx = dx / norm
            ny = dy / norm
            return nx, ny, ny, -nx, 0.5 * norm
    tx, ty, length = contact_tangent(x, y, n)
    nx = -ty
    ny = tx
    if nx * (to_x - from_x) + ny * (to_y - from_y) < 0.0:
        nx = -nx
        ny = -ny
    return nx, ny, ny, -nx, length
