"""The extension points are one table row each: a toy excitation kind, a toy contact law and a
toy limit state are added here, through their registries only, and run end to end.

A toy row reuses an existing kernel (a record table, the point law), so nothing outside this
file changes: every consumer (scene parsing, the time step, the dataset, labels, the IDA cube,
the fragility fits and figures) reads the row.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from stonedem.engine.laws import LAWS, Law
from stonedem.engine.run import run_scene
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import choose_time_step
from stonedem.errors import InputError
from stonedem.io.spec import REQUIRED, Field, Spec
from stonedem.kernels import excitation as kx
from stonedem.motion.excitation import EXCITATIONS, BaseMotion, Excitation
from stonedem.motion.records import record_to_table

BLOCK = {
    "bodies": [
        {
            "name": "base",
            "box": {"width": 4.0, "height": 0.5, "center": [0.0, -0.25]},
            "driven": True,
        },
        {"name": "block", "box": {"width": 0.5, "height": 2.0, "center": [0.0, 1.0]}},
    ],
    "friction": 0.7,
    "solver": {"duration": 0.5, "stop_on_collapse": False},
    "output": {"every": 0.01},
}


def _triangle_pulse(values, field, base_dir):
    """a(t) rises linearly to ``accel`` at T/2 and back to 0 at T = ``duration``: a table motion
    (``values``: the row's keys, already checked)."""
    a_p, t_p = values["accel"], values["duration"]
    time = np.linspace(0.0, t_p, 3)
    table_a, table_v, table_d, h = record_to_table(time, np.array([0.0, a_p, 0.0]))
    return BaseMotion(
        kx.KIND_TABLE,
        np.zeros(4),
        table_a,
        table_v,
        table_d,
        h,
        {"kind": "triangle_pulse", "accel": a_p, "duration": t_p, "pga": abs(a_p)},
    )


TRIANGLE = Excitation(
    Spec(
        (
            Field("accel", units="m s-2", default=REQUIRED, hint="give the peak in m/s2"),
            Field("duration", units="s", range="(0, inf)", default=REQUIRED),
        )
    ),
    _triangle_pulse,
    lambda d: f"triangle pulse {d['accel']:g} m/s2 x {d['duration']:g} s",
    pga=lambda m: float(np.abs(m.table_accel).max()),
    duration=lambda m: (len(m.table_accel) - 1) * m.table_dt,
    period=lambda m: (len(m.table_accel) - 1) * m.table_dt,
)


@pytest.fixture
def triangle(monkeypatch):
    monkeypatch.setitem(EXCITATIONS, "triangle_pulse", TRIANGLE)


def test_a_new_excitation_kind_is_one_row(triangle):
    spec = {**BLOCK, "excitation": {"kind": "triangle_pulse", "accel": 2.0, "duration": 0.2}}
    scene = scene_from_dict(json.loads(json.dumps(spec)))
    motion = scene.horizontal
    assert (
        motion.pga == 2.0
        and motion.duration == pytest.approx(0.2)
        and motion.shortest_period == pytest.approx(0.2)
    )
    # the base's velocity after the pulse is the pulse's area, a_p T / 2, exactly (table integrals)
    _, v, a = motion.evaluate([0.1, 0.3])
    assert a[0] == pytest.approx(2.0) and v[1] == pytest.approx(0.2, rel=1e-12) and a[1] == 0.0
    ds = run_scene(scene)
    assert json.loads(ds.attrs["excitation"])["kind"] == "triangle_pulse"
    assert motion.label == "triangle pulse 2 m/s2 x 0.2 s (PGA 2 m/s2)"
    # the block (b/h = 0.25, uplift at 2.45 m/s2) stays put under a 2 m/s2 pulse
    assert float(np.abs(ds.theta.sel(body="block")).max()) < 1e-4
    # an unknown key of the new kind is refused with the row's keys
    with pytest.raises(Exception, match="allowed keys: kind, accel, duration"):
        scene_from_dict(
            {
                **BLOCK,
                "excitation": {
                    "kind": "triangle_pulse",
                    "accel": 2.0,
                    "duration": 0.2,
                    "frequency": 1.0,
                },
            }
        )


def test_the_time_step_resolves_a_new_kind(triangle):
    """The row's period bounds the step (MIN_STEPS_PER_PERIOD steps per period), like every
    kind's."""
    spec = {
        **BLOCK,
        "contact": {"model": "area", "k_n": 1e6, "c_n": 0.0},
        "excitation": {"kind": "triangle_pulse", "accel": 1.0, "duration": 1e-3},
    }
    dt, _ = choose_time_step(scene_from_dict(spec))
    assert dt <= 1e-3 / 20 * (1 + 1e-12)


def test_a_new_contact_law_is_one_row(monkeypatch):
    """A point law with a parameter of its own (its dashpot in percent of critical), no plastic
    landing, its own defaults and step safety: its row here, the point kernel reused (a law of
    its own adds its kernel and its branch in stonedem.kernels.step.run: three files)."""
    percent = Field("zeta_percent", "number", "%", "[0, 1000]", 20.0, "give a percentage")
    monkeypatch.setitem(
        LAWS,
        "soft_point",
        Law(
            code=LAWS["point"].code,
            k_n=1.0e9,
            own=(percent,),
            kernel_params=lambda v: (v["zeta_percent"] / 100.0, 0.0),
            dt_safety=0.5,
            arm2=0.25,
            frames=("faces",),
            frame="faces",
            describe="toy: point contacts, no landing rule",
            damping_key="zeta_percent",
            pair_dashpot=lambda law, length, mass: (
                4.0 * law.zeta_percent / 100.0 * math.sqrt(0.5 * law.k_n * length * mass)
            ),
            loop=LAWS["point"].loop,
            hint="soft_point (a toy)",
        ),
    )
    scene = scene_from_dict({**BLOCK, "contact": {"model": "soft_point"}})
    assert scene.contact.params == {
        "k_n": 1e9,
        "zeta_percent": 20.0,
        "k_t": 1e9,
        "c_t": 0.0,
        "frame": "faces",
    }
    assert scene.dt_safety == 0.5 and scene.spec["contact"]["zeta_percent"] == 20.0
    ds = run_scene(scene)
    assert ds.attrs["contact_law"] == "toy: point contacts, no landing rule"
    assert ds.attrs["contact_model"] == "soft_point" and ds.attrs["contact_impact"] == "none"
    # at rest on its base: the static settlement m g / (k_n b) within 5 % (two end points)
    mass = scene.bodies[1].mass
    settle = 1.0 - float(ds.y.sel(body="block").isel(time=-1))
    assert settle == pytest.approx(mass * scene.gravity / (1e9 * 0.5), rel=0.05)
    # its parameter is checked by its field, and the other laws' keys are refused by name
    with pytest.raises(InputError, match=r"^contact\.zeta_percent: must be >= 0 and <= 1000"):
        scene_from_dict({**BLOCK, "contact": {"model": "soft_point", "zeta_percent": -5}})
    with pytest.raises(InputError, match="contact.c_n: not used by the soft_point model"):
        scene_from_dict({**BLOCK, "contact": {"model": "soft_point", "c_n": 1.0}})
    with pytest.raises(InputError, match="contact.zeta_percent: not used by the point model"):
        scene_from_dict({**BLOCK, "contact": {"model": "point", "zeta_percent": 1.0}})


def test_a_new_limit_state_is_one_row(monkeypatch, tmp_path):
    from stonedem.figures.fragility import fragility_curves_figure
    from stonedem.fragility.fit import fragility_dataset
    from stonedem.fragility.ida import LIMIT_STATES, LimitState, ida_cube
    from tests.fragility.test_ida import COLUMN, _search_file

    monkeypatch.setitem(
        LIMIT_STATES,
        "slight_rotation",
        LimitState(
            "max_rocking",
            lambda theta_cr, width: theta_cr / 100.0,
            "peak mean drum rotation exceeds theta_cr / 100",
            "rotation theta_cr / 100",
        ),
    )
    paths = []
    for comp, pga_c in (
        ("FF01a", 4.0),
        ("FF01b", 5.0),
        ("FF02a", 8.0),
        ("FF02b", 6.0),
        ("FF03a", 7.0),
    ):
        values = np.array([1.0, 2.0, 3.0, 4.0, 6.0, 9.0]) * pga_c / 4.0
        collapsed = values >= pga_c
        rocking = np.where(collapsed, 0.2, 0.001 * values**2)
        paths.append(
            _search_file(
                tmp_path / f"{comp}.nc",
                "col",
                comp,
                values,
                collapsed,
                rocking,
                np.zeros(values.size),
            )
        )
    cube = ida_cube(paths, {"col": COLUMN}, ["far_field"])
    assert "slight_rotation" in list(cube.limit_state.values)
    assert (
        cube.attrs["limit_state_slight_rotation"]
        == "peak mean drum rotation exceeds theta_cr / 100"
    )
    # theta_cr / 100 = 0.002 = 0.001 x^2 at x = sqrt(2), between runs 1 and 2 (x^2 interpolated
    # exactly)
    at = float(
        cube.pga_at_limit.sel(structure="col", record="FF01a", limit_state="slight_rotation")
    )
    assert at == pytest.approx(math.sqrt(2.0), rel=1e-6)
    fits = fragility_dataset(cube, samples=50)
    assert "slight_rotation" in list(fits.limit_state.values)
    fragility_curves_figure(cube, fits, "col", tmp_path / "curves.png")
    assert (tmp_path / "curves.png").stat().st_size > 0
