"""A scene's contact graph: which pairs touch on which faces, found once before a run.

Stacks and colonnades keep their contacts: drum k on drum k - 1's top face, a capital under
an epistyle. :func:`contact_graph` finds them from the packed scene at t = 0, as the general
loop's first sweep and separating-axis test would, so that
:mod:`stonedem.kernels.contact_graph` can run the scene without a broad phase or a search
for faces, and hand it to the general loop the step the graph stops holding.
"""

from __future__ import annotations

import math

import numpy as np

from stonedem.engine.pack import SceneArrays
from stonedem.kernels.broad_phase import body_bounds, find_candidate_pairs
from stonedem.kernels.contact_graph import BROKEN_FACES, BROKEN_PAIR, BROKEN_TURN, Graph
from stonedem.kernels.integrate import update_world_vertices
from stonedem.kernels.point_contact import world_edges

# a contact's faces count as each other's most opposed up to this share of the smallest
# angle between a face's normal and the other normals of its body (1 would be the tie)
TURN_SHARE = 0.9


def facing_edge(normals: np.ndarray, direction: np.ndarray) -> int:
    """The edge whose outward normal is closest to ``direction`` (the first of equals)."""
    score = np.where(np.any(normals != 0.0, axis=1), normals @ direction, -np.inf)
    return int(np.argmax(score))


def turn_room(normals: np.ndarray, k: int) -> float:
    """Half the smallest angle between edge k's normal and another edge's [rad]: the face
    stays its body's edge most opposed to a direction within that angle of its normal."""
    others = [i for i in range(len(normals)) if i != k and np.any(normals[i] != 0.0)]
    cosines = np.clip(normals[others] @ normals[k], -1.0, 1.0)
    return 0.5 * float(np.arccos(cosines).min()) if others else math.pi / 2


def contact_graph(arrays: SceneArrays) -> Graph:
    """The face contacts of the packed scene at t = 0: every pair the general loop's broad
    phase would list at its first sweep, on a's edge of least overlap with b and b's edge most
    opposed to it, with the relative turn up to which those stay the faces."""
    # the world vertices, bounds and edges of t = 0 by the loop's own kernels
    n_body, n_vert, start = len(arrays.body_mass), len(arrays.local_x), arrays.vert_start
    world_x, world_y, edge_len, edge_nx, edge_ny = (np.zeros(n_vert) for _ in range(5))
    update_world_vertices(
        n_body,
        start,
        arrays.local_x,
        arrays.local_y,
        arrays.init_x,
        arrays.init_y,
        arrays.init_theta,
        world_x,
        world_y,
        np.empty(n_body),
        np.empty(n_body),
    )
    lo_x, lo_y, hi_x, hi_y = (np.empty(n_body) for _ in range(4))
    body_bounds(n_body, start, world_x, world_y, lo_x, lo_y, hi_x, hi_y)
    world_edges(n_body, start, world_x, world_y, edge_len, edge_nx, edge_ny)
    spans = [slice(start[b], start[b + 1]) for b in range(n_body)]
    vertices = [np.column_stack([world_x[span], world_y[span]]) for span in spans]
    normals = [np.column_stack([edge_nx[span], edge_ny[span]]) for span in spans]
    pair_a, pair_b = find_candidate_pairs(
        n_body, arrays.body_driven, lo_x, lo_y, hi_x, hi_y, arrays.margin, arrays.sweep_axis
    )
    faces_a, faces_b, rest, limit = [], [], [], []
    index = np.full((n_body, n_body), -1, dtype=np.int64)
    for g, (a, b) in enumerate(zip(pair_a, pair_b)):
        normals_a, normals_b = normals[a], normals[b]
        # a's edge along whose normal b lies farthest out (least overlap, or a gap)
        separation = [
            np.min((vertices[b] - vertices[a][k]) @ normals_a[k])
            if np.any(normals_a[k] != 0.0)
            else -np.inf
            for k in range(len(normals_a))
        ]
        ka = int(np.argmax(separation))
        kb = facing_edge(normals_b, -normals_a[ka])
        inward = -normals_a[ka]
        angle = math.atan2(
            inward[0] * normals_b[kb][1] - inward[1] * normals_b[kb][0], inward @ normals_b[kb]
        )
        faces_a.append(ka)
        faces_b.append(kb)
        rest.append(angle - (arrays.init_theta[b] - arrays.init_theta[a]))
        limit.append(TURN_SHARE * min(turn_room(normals_a, ka), turn_room(normals_b, kb)))
        index[a, b] = g
    return Graph(
        pair_a=np.asarray(pair_a, dtype=np.int64),
        pair_b=np.asarray(pair_b, dtype=np.int64),
        face_a=np.asarray(faces_a, dtype=np.int64),
        face_b=np.asarray(faces_b, dtype=np.int64),
        turn_rest=np.asarray(rest, dtype=float),
        turn_limit=np.asarray(limit, dtype=float),
        index=index,
    )


def why_broken(broken: int, which: int, graph: Graph, names: list[str]) -> str:
    """What made the contact graph stop holding, in words (the dataset's general_because)."""
    if broken == BROKEN_PAIR:
        if which < 0:
            return "more pairs came within the broad phase's margin than the graph holds"
        a, b = divmod(which, len(names))
        return f"{names[a]} and {names[b]}, apart at t = 0, came within the broad phase's margin"
    a, b = names[graph.pair_a[which]], names[graph.pair_b[which]]
    if broken == BROKEN_TURN:
        return (
            f"the contact faces of {a} and {b} turned {graph.turn_limit[which]:.3g} rad "
            "against each other"
        )
    if broken == BROKEN_FACES:
        return f"{a} and {b} touched on other faces than at t = 0"
    return ""
