"""Time-loop bundles (stonedem.kernels.step) around a handful of bodies, for the contact-law
tests."""

import numpy as np

from stonedem.kernels import step
from stonedem.kernels.broad_phase import body_bounds
from stonedem.kernels.contact import N_ENERGY_ACC, N_MEMORY
from stonedem.kernels.excitation import KIND_NONE


def law_bundles(
    verts, start, centres, law, *, mass, inertia, driven, vel, mu, memory=None, pair_ft=None
):
    """(model, state, work) with bodies at their world vertices ``verts`` (n_vert, 2), pair (0, 1)
    the one candidate; vel (n_body, 3) mid-step velocities; mu the friction of every pair."""
    n = len(start) - 1
    still = step.Excitation(
        kind=KIND_NONE,
        params=np.zeros(4),
        table_accel=np.zeros(1),
        table_vel=np.zeros(1),
        table_disp=np.zeros(1),
        table_dt=1.0,
    )
    centres = np.asarray(centres, dtype=float)
    model = step.Model(
        vert_start=np.asarray(start, dtype=np.int64),
        local_x=verts[:, 0].copy(),
        local_y=verts[:, 1].copy(),
        body_mass=np.asarray(mass, dtype=float),
        body_inertia=np.asarray(inertia, dtype=float),
        body_driven=np.asarray(driven, dtype=np.bool_),
        body_radius=np.ones(n),
        ref_x=centres[:, 0].copy(),
        ref_y=centres[:, 1].copy(),
        ref_theta=np.zeros(n),
        pair_mu=np.full((n, n), float(mu)),
        body_group=np.full(n, -1, dtype=np.int64),
        group_theta_cr=np.zeros(0),
        group_lean=np.zeros(0),
        fall_depth=np.full(n, 1e9),
        margin=0.01,
        sweep_axis=1,
        gravity=9.81,
        law=law,
        horizontal=still,
        vertical=still,
        watch=step.Watch(
            rocking=np.zeros(n),
            n_rocking=0.0,
            onset_rocking=1.0,
            support=np.full(n, -1),
            slide_x=np.zeros(n),
            slide_y=np.zeros(n),
            slide_support_x=np.zeros(n),
            slide_support_y=np.zeros(n),
            slide_offset=np.zeros(n),
            epistyle=np.zeros(n),
            n_epistyle=0.0,
            x0=np.zeros(n),
        ),
        links=step.no_links(),
    )
    vel = np.asarray(vel, dtype=float)
    state = step.State(
        body_x=centres[:, 0].copy(),
        body_y=centres[:, 1].copy(),
        body_theta=np.zeros(n),
        body_vx=vel[:, 0].copy(),
        body_vy=vel[:, 1].copy(),
        body_omega=vel[:, 2].copy(),
        pair_ft=np.zeros((n, n)) if pair_ft is None else pair_ft,
        pair_memory=np.zeros((n, n, N_MEMORY)) if memory is None else memory,
        energy_acc=np.zeros(N_ENERGY_ACC),
        rest_count=np.zeros(1, dtype=np.int64),
        peaks=np.zeros(step.N_PEAK),
        peak_theta=np.zeros(n),
        events=np.full(step.N_EVENT, -1, dtype=np.int64),
        link_slip=np.zeros(0),
        link_status=np.zeros(0, dtype=np.int64),
        link_peak=np.zeros(0),
        link_energy=np.zeros(0),
    )
    work = step.allocate_work(model, 1)
    work.world_x[:] = verts[:, 0]
    work.world_y[:] = verts[:, 1]
    body_bounds(
        n, model.vert_start, work.world_x, work.world_y, work.lo_x, work.lo_y, work.hi_x, work.hi_y
    )
    work.pair_a[0], work.pair_b[0] = 0, 1
    return model, state, work
