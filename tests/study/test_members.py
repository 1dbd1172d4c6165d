"""Ensemble members (issue 44): the perturbation, the member dimension of a study, K = 1 as
today."""

import dataclasses

import numpy as np
import pytest
import xarray as xr

from stonedem.engine.scene import GEOMETRY_SCALE, initial_pose, posed_vertices, scene_from_dict
from stonedem.errors import InputError
from stonedem.study.cube import member_summary
from stonedem.study.grid import check_config, config_cases, ensemble_settings, load_config
from stonedem.study.members import (
    RELATIVE_STEP,
    TILT,
    member_scene,
    perturbation_rule,
    scale_factor,
    stiffness_factor,
)
from stonedem.study.runner import case_scene, run_case

SCHEMA = "workflow/schemas/config.schema.yaml"
COLUMN = {
    "structure": {"kind": "column", "n_drums": 3, "height": 6.0, "width": 1.0},
    "excitation": {"kind": "harmonic", "pga": 3.0, "frequency": 1.0},
    "solver": {"duration": 0.2},
}


@pytest.mark.parametrize("j", [1, 2, 7, 19, 999])
def test_a_stiffness_member_changes_k_n_by_exactly_j_ulps_and_nothing_else(j):
    scene = scene_from_dict(COLUMN)
    member = member_scene(scene, j)
    assert (
        member.contact.k_n
        == scene.contact.k_n * (1.0 - j * RELATIVE_STEP)
        == scene.contact.k_n * stiffness_factor(j)
    )
    # relative change j 2^-52, to the rounding of the product (k_n = 1e11 is not a power of two)
    assert (scene.contact.k_n - member.contact.k_n) / scene.contact.k_n == pytest.approx(
        j * 2.0**-52, rel=0.5 / j + 1e-9
    )
    assert member.contact.k_n != scene.contact.k_n
    assert member.contact.replace(k_n=scene.contact.k_n) == scene.contact
    for field in dataclasses.fields(scene):
        if field.name not in ("contact", "bodies", "horizontal", "vertical", "spec"):
            assert getattr(member, field.name) == getattr(scene, field.name), field.name
    assert member.bodies is scene.bodies and member.spec is scene.spec
    assert member.horizontal is scene.horizontal and member.vertical is scene.vertical


def test_member_zero_is_the_scene_itself():
    scene = scene_from_dict(COLUMN)
    assert member_scene(scene, 0) is scene and member_scene(scene, 0, "tilt") is scene


@pytest.mark.parametrize("j,sign", [(1, 1.0), (2, -1.0)])
def test_a_tilt_member_leans_the_whole_structure_by_1e_6_rad_onto_a_base_corner(j, sign):
    scene = scene_from_dict(COLUMN)
    member = member_scene(scene, j, "tilt")
    assert member.contact.k_n == scene.contact.k_n * stiffness_factor(j)
    free = [b for b in member.bodies if not b.driven]
    assert all(initial_pose(b)[2] == sign * TILT for b in free)
    base_top = max(v[1] for b in scene.bodies if b.driven for v in b.vertices)
    lowest = min(posed_vertices(b)[:, 1].min() for b in free)
    assert lowest >= base_top - 1e-15  # leans onto a corner, never into the base
    top = max(posed_vertices(b)[:, 1].max() for b in free)
    assert top - 6.0 == pytest.approx(
        1.0 * TILT, rel=1e-5
    )  # the far top corner rises by width x angle


@pytest.mark.parametrize("j", [1, 3, 19])
def test_a_geometry_member_scales_every_vertex_by_j_ulps_and_changes_k_n_as_stiffness_does(j):
    scene = scene_from_dict(COLUMN)
    member = member_scene(scene, j, "geometry")
    assert member.contact == member_scene(scene, j).contact
    assert scale_factor(j) == 1.0 + j * RELATIVE_STEP
    moved = 0
    for body, old in zip(member.bodies, scene.bodies):
        np.testing.assert_array_equal(body.vertices, old.vertices * scale_factor(j))
        assert (body.mass, body.inertia, body.driven, body.role) == (
            old.mass,
            old.inertia,
            old.driven,
            old.role,
        )
        moved += int(np.count_nonzero(body.vertices != old.vertices))
    assert moved > 0  # the last bits do move: a factor that rounded back to 1 would change nothing
    np.testing.assert_allclose(
        np.vstack([b.vertices for b in member.bodies]),
        np.vstack([b.vertices for b in scene.bodies]),
        rtol=25 * RELATIVE_STEP,
        atol=0,
    )
    assert member_scene(scene, 0, "geometry") is scene
    assert "every vertex" in perturbation_rule("geometry") and perturbation_rule(
        "stiffness"
    ).endswith("2^-52")


def test_scenes_built_under_a_geometry_scale_have_every_vertex_scaled_and_only_then():
    plain = scene_from_dict(COLUMN)
    token = GEOMETRY_SCALE.set(scale_factor(2))
    try:
        scaled = scene_from_dict(COLUMN)
    finally:
        GEOMETRY_SCALE.reset(token)
    for body, old in zip(scaled.bodies, plain.bodies):
        np.testing.assert_array_equal(body.vertices, old.vertices * scale_factor(2))
    assert [b.vertices.tobytes() for b in member_scene(plain, 2, "geometry").bodies] == [
        b.vertices.tobytes() for b in scaled.bodies
    ]
    again = scene_from_dict(COLUMN)  # the scale is gone once its block ends
    assert all(
        np.array_equal(b.vertices, old.vertices) for b, old in zip(again.bodies, plain.bodies)
    )


def test_bad_members_are_refused():
    scene = scene_from_dict(COLUMN)
    for j in (-1, 1000, 1.5, True):
        with pytest.raises(InputError):
            member_scene(scene, j)
    with pytest.raises(InputError, match="perturbation"):
        member_scene(scene, 1, "dt")


def _config(**ensemble):
    config = load_config("config/config.yaml", "config/quick.yaml")
    if ensemble:
        config["ensemble"] = ensemble
    return config


def test_one_member_is_the_study_as_configured_and_k_members_multiply_every_case():
    plain = config_cases(_config())
    assert config_cases(_config(members=1)) == plain
    three = config_cases(_config(members=3, perturbation="tilt"))
    for study, cases in plain.items():
        if "members" in _config()["studies"][study]:  # its own ensemble: the next test
            continue
        assert len(three[study]) == 3 * len(cases)
        for case, members in zip(cases, zip(*[iter(three[study])] * 3)):
            assert [m.params for m in members] == [{**case.params, "member": j} for j in range(3)]
            assert [m.id for m in members] == [f"{case.id}_m-{j}" for j in range(3)]
            assert all(m.search == case.search for m in members)
            assert members[2].scene["ensemble"] == {"member": 2, "perturbation": "tilt"}


def test_a_study_s_own_members_override_the_config_s():
    config = _config(members=3)
    config["studies"] = {"seq": dict(config["studies"]["sequence_records"], members=5)}
    config["studies"]["ramp"] = dict(_config()["studies"]["ramp_drums"])
    cases = config_cases(config)
    n_seq = len(config_cases({**config, "ensemble": None}, ["seq"])["seq"]) // 5
    assert len(cases["seq"]) == 5 * n_seq and cases["seq"][4].params["member"] == 4
    assert len(cases["ramp"]) == 3 * len(config_cases({**config, "ensemble": None})["ramp"])
    from stonedem.study.grid import STUDY
    from stonedem.study.members import MAX_MEMBERS

    assert STUDY["members"].range == f"[1, {MAX_MEMBERS}]"
    for bad in (0, 1001, 2.5, "five"):
        config["studies"]["seq"]["members"] = bad
        with pytest.raises(InputError) as error:
            check_config(config)
        assert error.value.field == "studies.seq.members"


def test_member_zero_of_an_ensemble_runs_bit_for_bit_as_the_case():
    config = _config(members=2)
    config["studies"] = {"ramp_drums": config["studies"]["ramp_drums"]}
    config["studies"]["ramp_drums"]["grid"] = {"n_drums": [2]}
    config["studies"]["ramp_drums"]["solver"] = {"duration": 1.5}
    case, member0, member1 = (
        config_cases({**config, "ensemble": None})["ramp_drums"]
        + config_cases(config)["ramp_drums"]
    )
    plain, zero, one = (
        run_case(case, "records"),
        run_case(member0, "records"),
        run_case(member1, "records"),
    )
    assert int(zero["member"]) == 0 and zero.attrs["ensemble_perturbation"] == "stiffness"
    for name in plain.data_vars:
        np.testing.assert_array_equal(zero[name].values, plain[name].values, err_msg=name)
    assert case_scene(member1, "records").contact.k_n == case_scene(
        case, "records"
    ).contact.k_n * stiffness_factor(1)
    assert not np.array_equal(one["x"].values, plain["x"].values)  # the last bits do move


@pytest.mark.parametrize(
    "ensemble,field",
    [
        ({"members": 0}, "ensemble.members"),
        ({"members": "3"}, "ensemble.members"),
        ({"perturbation": "dt"}, "ensemble.perturbation"),
        ({"size": 3}, "ensemble"),
        ([3], "ensemble"),
        ({"baseline_members": 1}, "ensemble.baseline_members"),
    ],
)
def test_a_bad_ensemble_setting_is_refused_by_its_config_path(ensemble, field):
    config = _config()
    config["ensemble"] = ensemble
    with pytest.raises(InputError) as error:
        check_config(config, schema=SCHEMA)
    assert error.value.field == field and "\n" not in str(error.value)
    with pytest.raises(InputError):
        ensemble_settings(config)


def test_member_is_not_a_swept_parameter():
    config = _config()
    config["studies"]["ramp_drums"]["grid"]["member"] = [0, 1]
    with pytest.raises(InputError, match="ensemble: {members: K}") as error:
        check_config(config, schema=SCHEMA)
    assert error.value.field == "studies.ramp_drums.grid.member"


def test_ensemble_settings_default_to_one_member_and_a_baseline_of_twenty():
    assert ensemble_settings({}) == (1, "stiffness")
    assert ensemble_settings({}, baseline=True) == (20, "stiffness")
    assert ensemble_settings(
        {"ensemble": {"members": 4, "baseline_members": 8}}, baseline=True
    ) == (8, "stiffness")


def test_a_cube_of_members_reads_as_collapse_fractions_and_medians():
    collapsed = np.array([[1, 0, 1, 1], [0, 0, 0, 0], [1, 1, 1, 1]], dtype=float)
    rocking = np.array([[0.3, 0.1, 0.2, 0.4], [0.01, 0.02, 0.03, 0.04], [1.0, 1.0, 1.0, 1.0]])
    cube = xr.Dataset(
        {
            "collapsed": (("pga", "member"), collapsed),
            "max_rocking": (("pga", "member"), rocking),
            "rocking": (("pga", "member", "time"), np.arange(24.0).reshape(3, 4, 2)),
        },
        coords={"pga": [1.0, 2.0, 3.0], "member": [0, 1, 2, 3], "time": [0.0, 0.1]},
    )
    summary = member_summary(cube)
    np.testing.assert_array_equal(summary["collapsed"].values, [0.75, 0.0, 1.0])
    np.testing.assert_allclose(summary["max_rocking"].values, [0.25, 0.025, 1.0])
    np.testing.assert_array_equal(summary["rocking"].values, cube["rocking"].sel(member=0).values)
    assert summary.attrs["members"] == 4 and "member" not in summary.dims
    assert member_summary(cube.sel(member=0)) is not None


def test_an_ensemble_too_large_for_the_workflow_is_refused_by_its_config_path():
    config = load_config("config/config.yaml")
    config["ensemble"] = {
        "members": 999
    }  # 555 cases x 999: 554 445 runs, a DAG that would never plan
    with pytest.raises(InputError, match="MAX_MEMBER_CASES") as error:
        check_config(config, schema=SCHEMA)
    assert error.value.field == "ensemble.members"
    config["ensemble"] = {"members": 20}  # the stored baseline's size passes
    assert sum(map(len, check_config(config, schema=SCHEMA).values())) == 555
