"""The reference scenes the benchmarks and the equivalence test share: a lone rocking block,
columns of 1, 8 and 30 drums and colonnades under the Athens stand-in, at the study's contact
settings (:data:`SCENES`, timed by :mod:`benchmarks.kernel`), and the short-horizon members
built from them (:func:`short_horizon_members`: layer B of :mod:`stonedem.study.exact_checks`,
and the GPU checks of :mod:`benchmarks.gpu_check`)."""

from __future__ import annotations

RECORD = "records/athens_standin_kocaeli_arc000.nc"  # the Athens stand-in (thesis Table 6.1)


def _column(n_drums, duration):
    return {
        "structure": {
            "kind": "column",
            "n_drums": n_drums,
            "height": 6.0,
            "width": 1.0,
            "capital": {"height": 0.6, "width": 1.4},
        },
        "friction": 0.485,
        "contact": {"model": "point", "k_n": 1e10},
        "excitation": {"kind": "record", "file": RECORD, "pga": 4.0},
        "solver": {"duration": duration, "dt": "auto", "dt_safety": 1.0, "stop_on_collapse": False},
        "output": {"every": 0.01},
    }


def _colonnade(n_columns, duration):
    spec = _column(3, duration)
    spec["structure"] = {
        "kind": "colonnade",
        "n_columns": n_columns,
        "n_drums": 3,
        "height": 6.0,
        "width": 1.0,
        "clear_distance": 2.0,
        "epistyle_type": "a",
        "capital": {"height": 0.6, "width": 1.4},
    }
    return spec


def _lone_block(duration):
    from stonedem.validation.cases import block_scene

    # released from 0.1 rad (alpha = 0.245 rad): rocks freely and comes to rest
    return block_scene(
        0.4,
        1.6,
        contact={"model": "point", "k_n": 1e10},
        tilt=0.1,
        duration=duration,
        every=0.01,
        friction=0.7,
    )


# name -> (title, scene dict builder of the duration [s]); point law, k_n 1e10, auto dt,
# output every 0.01 s (the study's settings), Athens stand-in at 4 m/s2 where excited
SCENES = {
    "lone_block": ("lone 0.4 x 1.6 m block rocking freely from 0.1 rad", _lone_block),
    "column_1": ("6 x 1 m column, 1 drum + capital", lambda d: _column(1, d)),
    "column_8": ("6 x 1 m column, 8 drums + capital", lambda d: _column(8, d)),
    "column_30": ("6 x 1 m column, 30 drums + capital", lambda d: _column(30, d)),
    "colonnade_3x3": (
        "colonnade, 3 columns x 3 drums, epistyle type a",
        lambda d: _colonnade(3, d),
    ),
    "colonnade_10x3": (
        "a row of 10 columns x 3 drums under epistyles type a",
        lambda d: _colonnade(10, d),
    ),
}


def short_horizon_members(duration: float) -> dict[str, list]:
    """{scene kind: member scenes} sharing a structure within each kind."""
    from stonedem.engine.scene import scene_from_dict

    def members(name, **changes):
        out = []
        for pga in (3.0, 9.0):
            spec = SCENES[name][1](duration)
            for key, value in changes.items():
                spec[key] = value
            if "pga" in spec.get("excitation", {}):
                spec["excitation"] = {**spec["excitation"], "pga": pga}
            out.append(scene_from_dict(spec))
        return out

    return {
        "lone_block": members("lone_block"),
        "column_8_record": members("column_8"),
        "colonnade_harmonic": members(
            "colonnade_3x3", excitation={"kind": "harmonic", "pga": 6.0, "frequency": 2.0}
        ),
        "column_1_area_law": members("column_1", contact={"model": "area", "k_n": 1e9, "c_n": 1e4}),
    }
