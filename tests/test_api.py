"""The public face (stonedem.api, re-exported by the package): scenes and walls run from files
and mappings, the study's files opened and checked, wrong files refused with one line naming
the fix, and ``import stonedem`` alone loading no engine."""

import ast
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

import stonedem
from stonedem.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "tests" / "data" / "scenes" / "rocking_block.yaml"
WALL = ROOT / "config" / "walls" / "free_standing.yaml"
SHORT = {"solver.duration": 0.3}


# --- the face ---------------------------------------------------------------------------------


def loaded_after(code: str) -> set[str]:
    out = subprocess.run(
        [
            sys.executable,
            "-c",
            code + "\nimport sys\n"
            "print(sorted({n.split('.')[1] for n in sys.modules if n.startswith('stonedem.')}))",
        ],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return set(ast.literal_eval(out.strip().splitlines()[-1]))


def test_import_stonedem_alone_loads_no_engine():
    assert loaded_after("import stonedem") <= {"version"}
    # a name of the face loads the face, still not the engine (it is loaded on first use)
    loaded = loaded_after("import stonedem\nstonedem.open_cube\nstonedem.InputError")
    assert "api" in loaded and not loaded & {
        "engine",
        "kernels",
        "study",
        "fragility",
        "wall",
        "figures",
    }, loaded


def test_the_package_names_the_face():
    from stonedem import api

    assert set(api.__all__) <= set(stonedem.__all__) and set(api.__all__) <= set(dir(stonedem))
    for name in api.__all__:
        assert getattr(stonedem, name) is getattr(api, name)
    from stonedem.io.netcdf import write_dataset

    assert stonedem.write_dataset is write_dataset and stonedem.InputError is InputError
    with pytest.raises(AttributeError, match="no attribute 'nothing_here'"):
        stonedem.nothing_here  # noqa: B018


# --- scenes -----------------------------------------------------------------------------------


def test_load_scene_from_a_file_or_a_mapping_with_overrides():
    by_list = stonedem.load_scene(SCENE, overrides=["solver.duration=0.3", "bodies.block.mass=10"])
    by_map = stonedem.load_scene(
        str(SCENE), overrides={"solver.duration": 0.3, "bodies.block.mass": 10.0}
    )
    spec = yaml.safe_load(SCENE.read_text())
    by_dict = stonedem.load_scene(
        spec, base_dir=SCENE.parent, overrides={"solver.duration": 0.3, "bodies.block.mass": 10.0}
    )
    for scene in (by_list, by_map, by_dict):
        assert scene.duration == 0.3 and scene.body_names == ["base", "block"]
        assert scene.bodies[1].mass == 10.0
    assert spec["solver"]["duration"] == 4.0, "the caller's mapping is left as it was"


@pytest.mark.parametrize(
    "source, overrides, message",
    [
        (ROOT / "no_such_scene.yaml", None, "scene file not found; check the path"),
        (42, None, "scene: expected a scene file path or a mapping, got int; give the path"),
        (
            SCENE,
            {"bodies.nobody.mass": 1.0},
            "overrides bodies.nobody: no list item 'nobody'; use an index or a body name",
        ),
        (SCENE, ["solver.duration"], "--set: 'solver.duration' is not key=value"),
        (
            SCENE,
            "solver.duration=1",
            "overrides: expected a list of key=value strings or a mapping",
        ),
        (
            {"bodies": []},
            None,
            "bodies: the scene has no bodies; list bodies: or give a structure:",
        ),
    ],
)
def test_load_scene_refuses_bad_input_naming_the_fix(source, overrides, message):
    with pytest.raises(InputError) as err:
        stonedem.load_scene(source, overrides=overrides)
    assert message in str(err.value) and "\n" not in str(err.value)


@pytest.fixture(scope="module")
def rocking():
    return stonedem.run_scene(stonedem.load_scene(SCENE, overrides=SHORT))


def test_run_scene_from_a_scene_a_file_or_a_mapping(rocking):
    ds = rocking
    assert isinstance(ds, xr.Dataset) and ds["theta"].attrs["units"] == "rad"
    assert float(ds["time"][-1]) == pytest.approx(0.3)
    theta0 = float(ds["theta"].sel(body="block").isel(time=0))
    assert abs(theta0) == pytest.approx(0.05236), "released from its tilt"
    spec = yaml.safe_load(SCENE.read_text())
    spec["solver"]["duration"] = 0.3
    from_dict = stonedem.run_scene(spec)
    assert np.array_equal(from_dict["theta"].values, ds["theta"].values), (
        "the same scene, the same run"
    )
    with pytest.raises(InputError, match="scene file not found"):
        stonedem.run_scene(ROOT / "missing.yaml")


def test_the_command_line_runs_through_the_face(tmp_path, rocking):
    from stonedem.cli import main

    out = tmp_path / "rocking.nc"
    assert main(["run", str(SCENE), "-o", str(out), "--set", "solver.duration=0.3", "-q"]) == 0
    with xr.open_dataset(out) as ds:
        assert np.allclose(ds["theta"].values, rocking["theta"].values)


# --- walls ------------------------------------------------------------------------------------


def small_wall() -> dict:
    """tests/wall/test_pushover.py's free-standing wall: 2 blocks x 8 courses, overturns at s/H."""
    return {
        "panel": {
            "block": {"a": 0.081, "b": 0.210, "s": 0.070},
            "blocks_per_course": 2,
            "courses": 8,
            "unit_weight": 20000.0,
        },
        "joints": {"kind": "dry", "mu": 0.7, "k_n": 2.4e9, "k_t": 1.0e9},
        "restraints": [{"edge": "base", "fix": "all"}],
        "load": {"kind": "proportional", "direction": "out_of_plane"},
    }


def test_run_wall_from_a_mapping_and_from_a_case_file():
    ds = stonedem.run_wall(small_wall())
    assert ds["lambda"].dims == ("step",) and ds["control_displacement"].attrs["units"] == "m"
    assert float(ds.lambda_max) == pytest.approx(0.070 / (8 * 0.081), rel=0.02)
    from_file = stonedem.run_wall(WALL)
    reference = yaml.safe_load(WALL.read_text())["reference"]["lambda_analytic"]
    assert float(from_file.lambda_max) == pytest.approx(reference, rel=0.02)
    assert from_file.attrs["title"].endswith("free_standing")


@pytest.mark.parametrize(
    "case, message",
    [
        (ROOT / "no_such_wall.yaml", "a wall case file not found; check the path"),
        (
            {**small_wall(), "joints": {"kind": "dry", "mu": -1.0, "k_n": 2.4e9, "k_t": 1.0e9}},
            "joints.mu",
        ),
        (3.5, "case: expected a wall case file path or a mapping, got float"),
    ],
)
def test_run_wall_refuses_bad_input_naming_the_field(case, message):
    with pytest.raises(InputError, match=message.replace(".", r"\.")):
        stonedem.run_wall(case)


# --- the study's files ------------------------------------------------------------------------


def case_file(path, pga, collapsed, rocking):
    """A case file as stonedem.study.runner.run_case writes it (the variables a cube keeps)."""
    ds = xr.Dataset(
        {
            "collapsed": ((), float(collapsed), {"units": "1", "long_name": "collapsed"}),
            "max_rocking": ((), rocking, {"units": "rad", "long_name": "peak rocking"}),
        },
        coords={"pga": ((), pga, {"units": "m s-2", "long_name": "PGA"})},
        attrs={"study": "tiny", "title": "stonedem rigid-block simulation: tiny"},
    )
    return stonedem.write_dataset(ds, path)


@pytest.fixture(scope="module")
def study_files(tmp_path_factory):
    """One file of each kind, written by the project's own functions and writer."""
    from stonedem.fragility.fit import fragility_dataset
    from stonedem.fragility.ida import ida_cube
    from stonedem.study.cube import combine_cases, search_dataset
    from stonedem.study.grid import Case
    from stonedem.study.search import Run, SearchSettings, summary
    from tests.fragility.test_ida import COLUMN, _search_file

    d = tmp_path_factory.mktemp("study")
    runs = [Run(1.0, False, "hunt"), Run(1.8, True, "hunt"), Run(1.4, False, "bisect")]
    cases = [
        case_file(d / f"pga-{r.value:g}.nc", r.value, r.collapsed, 0.1 * r.value) for r in runs
    ]
    files = {"scene": cases[0], "cube": stonedem.write_dataset(combine_cases(cases), d / "cube.nc")}
    settings = SearchSettings(start=1.0, tolerance=0.3, fill=0)
    system = Case("tiny", "block", {}, {}, settings)
    files["search"] = stonedem.write_dataset(
        search_dataset(system, runs, cases, summary(runs, settings)), d / "search.nc"
    )
    searches = []
    for comp, pga_c in (("FF01a", 4.0), ("FF01b", 5.0), ("FF02a", 8.0)):
        values = np.array([1.0, 2.0, 3.0, 4.0, 6.0]) * pga_c / 4.0
        collapsed = values >= pga_c
        searches.append(
            _search_file(
                d / f"ida_{comp}.nc",
                "col",
                comp,
                values,
                collapsed,
                np.where(collapsed, 0.2, 0.001 * values**2),
                np.zeros(values.size),
            )
        )
    ida = ida_cube(searches, {"col": COLUMN}, ["far_field"])
    files["ida"] = stonedem.write_dataset(ida, d / "ida.nc")
    files["fragility"] = stonedem.write_dataset(
        fragility_dataset(ida, samples=20), d / "fragility.nc"
    )
    (d / "notes.txt").write_text("not a NetCDF file\n")
    files["text"] = d / "notes.txt"
    files["untitled"] = stonedem.write_dataset(xr.Dataset({"x": ((), 1.0)}), d / "untitled.nc")
    return files


OPENERS = {
    "cube": "open_cube",
    "search": "open_search",
    "ida": "open_ida",
    "fragility": "open_fragility",
}


def test_each_kind_of_file_opens_in_memory(study_files):
    cube = stonedem.open_cube(study_files["cube"])
    assert cube.sizes["pga"] == 3 and cube["collapsed"].sel(pga=1.8) == 1
    search = stonedem.open_search(study_files["search"])
    assert float(search.collapse_threshold) == 1.8 and float(search.survived_below_threshold) == 1.4
    assert list(search["pga"].values) == [1.0, 1.4, 1.8], "runs sorted by the searched value"
    ida = stonedem.open_ida(study_files["ida"])
    collapse = ida.pga_at_limit.sel(
        structure="col", limit_state="collapse", record=["FF01a", "FF01b", "FF02a"]
    )
    assert (
        collapse.values.tolist() == [4.0, 5.0, 8.0] and ida.pga_at_limit.attrs["units"] == "m s-2"
    )
    fits = stonedem.open_fragility(study_files["fragility"])
    median = float(
        fits.median_pga.sel(structure="col", record_set="far_field", limit_state="collapse")
    )
    assert median == pytest.approx((4.0 * 5.0 * 8.0) ** (1 / 3))


def test_an_opened_file_is_in_memory_and_closed(study_files, tmp_path):
    import shutil

    path = Path(shutil.copy(study_files["cube"], tmp_path / "cube.nc"))
    cube = stonedem.open_cube(path)
    path.unlink()  # nothing holds the file: it may be rewritten by the workflow meanwhile
    assert cube["max_rocking"].values.tolist() == pytest.approx([0.1, 0.14, 0.18])


@pytest.mark.parametrize("kind", list(OPENERS))
def test_a_file_of_another_kind_is_refused_naming_its_opener(study_files, kind):
    opener = getattr(stonedem, OPENERS[kind])
    for other, other_opener in OPENERS.items():
        if other == kind:
            continue
        with pytest.raises(InputError) as err:
            opener(study_files[other])
        message = str(err.value)
        assert f"open it with stonedem.{other_opener}" in message and "\n" not in message, message
    with pytest.raises(
        InputError, match=r"is a rigid-block simulation, not .*; give .* written by"
    ):
        opener(study_files["scene"])
    with pytest.raises(InputError, match=r"is not .* \(title ''\); give .* written by stonedem\."):
        opener(study_files["untitled"])


@pytest.mark.parametrize("kind", list(OPENERS))
def test_a_text_file_a_missing_file_and_a_folder_are_refused(study_files, kind, tmp_path):
    opener = getattr(stonedem, OPENERS[kind])
    with pytest.raises(
        InputError, match=r"notes\.txt: not a NetCDF file; give .* \(\.nc\) written by stonedem\."
    ):
        opener(study_files["text"])
    with pytest.raises(
        InputError,
        match=r"nothing\.nc: file not found; check the path, or write .* with stonedem\.",
    ):
        opener(tmp_path / "nothing.nc")
    with pytest.raises(InputError, match="is not a regular file; give the path of"):
        opener(tmp_path)
    with pytest.raises(InputError, match="path: expected a file path, got int"):
        opener(3)


def test_a_run_of_the_engine_is_not_a_study_file(tmp_path, rocking):
    path = stonedem.write_dataset(rocking, tmp_path / "rocking.nc")
    with pytest.raises(
        InputError, match="rocking.nc: is a rigid-block simulation, not an IDA cube; give"
    ):
        stonedem.open_ida(path)


def test_every_public_name_has_a_numpydoc_docstring():
    import stonedem

    for name in stonedem.__all__:
        if name.startswith("__"):
            continue
        doc = getattr(stonedem, name).__doc__ or ""
        assert "Parameters\n" in doc and "----------" in doc, (
            f"stonedem.{name}: no numpydoc Parameters section"
        )


def test_run_scenes_gives_each_scene_what_run_scene_gives_it():
    spec = {
        "bodies": [
            {
                "name": "base",
                "box": {"width": 2.0, "height": 0.2, "center": [0.0, -0.1]},
                "driven": True,
            },
            {
                "name": "block",
                "box": {"width": 0.2, "height": 1.0, "center": [0.0, 0.5]},
                "tilt": {"angle": 0.05, "about": "bottom_right"},
            },
        ],
        "solver": {"duration": 0.3},
    }
    other = {**spec, "solver": {"duration": 0.2}}
    together = stonedem.run_scenes([spec, other])
    for source, ds in zip([spec, other], together):
        alone = stonedem.run_scene(source)
        assert ds.attrs["device"] == "cpu"
        assert ds["theta"].equals(alone["theta"]) and ds["x"].equals(alone["x"])
    with pytest.raises(stonedem.InputError, match="device"):
        stonedem.run_scenes([spec], device="abacus")


# --- numpy values are numbers ----------------------------------------------------------------


def test_numpy_scalars_and_0d_arrays_are_numbers_everywhere():
    """A script's np.float32 friction, np.int64 drum count or 0-d array is the number it holds
    (refused before: 'expected a number'); np.bool_ stays refused like bool."""
    plain = {
        "structure": {"kind": "column", "n_drums": 3, "height": 3.0},
        "friction": 0.625,
        "solver": {"duration": 0.05},
    }
    numpy = {
        "structure": {"kind": "column", "n_drums": np.int64(3), "height": np.array(3.0)},
        "friction": np.float32(0.625),
        "solver": {"duration": np.float64(0.05)},
    }
    a, b = stonedem.load_scene(plain), stonedem.load_scene(numpy)
    assert len(b.bodies) == 4 and b.friction == 0.625 and b.duration == 0.05
    assert [body.mass for body in a.bodies] == [body.mass for body in b.bodies]
    for bad, field in ((np.True_, "friction"), (np.array([0.5, 0.6]), "friction")):
        with pytest.raises(InputError, match=f"^{field}: expected a number"):
            stonedem.load_scene({**plain, field: bad})
    with pytest.raises(InputError, match=r"structure\.n_drums: must be an integer"):
        stonedem.load_scene({**plain, "structure": {"kind": "column", "n_drums": np.float32(2.5)}})
    from stonedem.wall.case import check_case

    wall = small_wall()
    wall["panel"]["courses"] = np.int64(8)
    wall["joints"]["mu"] = np.float32(0.75)
    case = check_case(wall)
    assert case.courses == 8 and type(case.courses) is int
    assert (
        case.spec
        == check_case(small_wall() | {"joints": {**small_wall()["joints"], "mu": 0.75}}).spec
    )


# --- write_dataset ---------------------------------------------------------------------------


def test_write_dataset_refuses_to_replace_what_it_did_not_write(tmp_path, rocking):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE.read_text().replace("duration: 4.0", "duration: 0.02"))
    ds = stonedem.run_scene(scene)
    assert ds.attrs["scene_file"] == str(scene)
    for overwrite in (False, True):  # an input of the dataset, whatever the flag
        with pytest.raises(InputError, match=r"scene\.yaml is the input file"):
            stonedem.write_dataset(ds, scene, overwrite=overwrite)
    ds.attrs.pop(
        "scene_file"
    )  # loaded first: the dataset does not know its file, the file is no NetCDF
    with pytest.raises(
        InputError, match=r"scene\.yaml exists and is not a NetCDF file; it is not replaced"
    ):
        stonedem.write_dataset(ds, scene)
    (tmp_path / "notes.nc").write_text("notes\n")
    xr.Dataset({"a": ((), 1.0)}).to_netcdf(tmp_path / "foreign.nc")
    with pytest.raises(
        InputError, match="notes.nc exists and is not a NetCDF file.*pass overwrite=True"
    ):
        stonedem.write_dataset(rocking, tmp_path / "notes.nc")
    with pytest.raises(InputError, match="foreign.nc is a NetCDF file stonedem did not write"):
        stonedem.write_dataset(rocking, tmp_path / "foreign.nc")
    assert (
        scene.read_text().startswith(SCENE.read_text()[:20])
        and (tmp_path / "notes.nc").read_text() == "notes\n"
    )
    # its own files, and anything with overwrite=True, are replaced
    for name in ("ours.nc", "ours.nc", "notes.nc"):
        stonedem.write_dataset(rocking, tmp_path / name, overwrite=name == "notes.nc")
        with xr.open_dataset(tmp_path / name) as back:
            assert back.sizes["time"] == rocking.sizes["time"]


@pytest.mark.parametrize(
    "ds, field",
    [
        (xr.Dataset({"z": (("t",), np.array([1 + 2j]))}), "ds['z']: has dtype complex128"),
        (xr.Dataset({"x": (("t",), np.zeros(2, np.float16))}), "ds['x']: has dtype float16"),
        (xr.Dataset({"x": ((), 1.0)}, attrs={"a": {"b": 1}}), "ds.attrs['a']: is a dict"),
        (xr.Dataset({"x": ((), 1.0)}, attrs={"a": None}), "ds.attrs['a']: is a NoneType"),
        (xr.Dataset({"x": ((), 1.0)}, attrs={"a": True}), "ds.attrs['a']: is a bool"),
        (xr.Dataset({"x": ((), 1.0)}, attrs={"a": [[1, 2]]}), "ds.attrs['a']: is a sequence"),
        (xr.Dataset({"x": ((), 1.0, {"units": None})}), "ds['x'].attrs['units']: is a NoneType"),
        (xr.Dataset({"a/b": ((), 1.0)}), "ds['a/b']: a variable or dimension name"),
        (xr.Dataset({1: ((), 1.0)}), "ds[1]: a variable or dimension name"),
        (
            xr.Dataset({"x": (("t",), np.array([1, "a"], dtype=object))}),
            "ds: cannot be written as NetCDF (ValueError",
        ),
    ],
)
def test_write_dataset_names_what_netcdf_cannot_hold(tmp_path, ds, field):
    with pytest.raises(InputError) as err:
        stonedem.write_dataset(ds, tmp_path / "out.nc")
    assert str(err.value).startswith(field) and "\n" not in str(err.value)
    assert list(tmp_path.iterdir()) == [], "nothing written"


def test_write_dataset_checks_its_arguments_first(tmp_path, rocking):
    (tmp_path / "loop.nc").symlink_to("loop.nc")
    for args, kind, start in [
        ((None, tmp_path / "o.nc"), TypeError, "ds: expected an xarray.Dataset, got NoneType"),
        ((rocking["theta"], tmp_path / "o.nc"), TypeError, "ds: expected an xarray.Dataset"),
        ((rocking, None), TypeError, "path: expected a file path"),
        (
            (rocking, b"o.nc"),
            TypeError,
            "path: expected a file path (str or os.PathLike), got bytes",
        ),
        ((rocking, tmp_path), InputError, "path: "),
        ((rocking, tmp_path / "loop.nc"), InputError, "path: "),
        ((rocking, tmp_path / "o.nc", [1]), TypeError, "encoding: expected a dict"),
    ]:
        with pytest.raises(kind) as err:
            stonedem.write_dataset(*args)
        assert str(err.value).startswith(start) and "\n" not in str(err.value), err.value
    with pytest.raises(TypeError, match="^overwrite: expected True or False"):
        stonedem.write_dataset(rocking, tmp_path / "o.nc", overwrite="yes")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["loop.nc"]


# --- the API's arguments ---------------------------------------------------------------------


def test_a_loaded_scene_cannot_record_a_false_provenance():
    scene = stonedem.load_scene(SCENE, overrides=SHORT)
    for change in (
        lambda s: s.spec.__setitem__("friction", 0.9),
        lambda s: s.spec["solver"].update(duration=9.0),
        lambda s: s.spec["bodies"][1].__setitem__("mass", 1.0),
        lambda s: s.spec.pop("solver"),
    ):
        with pytest.raises(TypeError, match="scene.spec is read-only"):
            change(scene)
    import copy
    import json

    edited = copy.deepcopy(scene.spec)
    edited["friction"] = 0.9  # a copy is a plain dict, loaded again as a new scene
    assert stonedem.load_scene(edited, base_dir=SCENE.parent).friction == 0.9
    assert json.loads(json.dumps(scene.spec))["friction"] == scene.friction != 0.9


def test_run_scenes_takes_one_scene_or_many_and_names_a_bad_argument(tmp_path):
    scene = stonedem.load_scene(SCENE, overrides={"solver.duration": 0.02})
    assert len(stonedem.run_scenes(scene)) == 1
    short = tmp_path / "short.yaml"
    short.write_text(SCENE.read_text().replace("duration: 4.0", "duration: 0.02"))
    for one in (str(short), short):  # a path is one scene, not its characters
        (ds,) = stonedem.run_scenes(one)
        assert ds.attrs["scene_file"] == str(short) and float(ds["time"][-1]) == pytest.approx(0.02)
    for bad, message in (
        (None, "scenes: expected a scene"),
        (3, "got int"),
        ([scene, 3], r"scenes\[1\]: expected"),
        (iter([None]), r"scenes\[0\]"),
    ):
        with pytest.raises(TypeError, match=message):
            stonedem.run_scenes(bad)
    for call, message in (
        (lambda: stonedem.run_scenes([scene], threads="2"), "threads: expected"),
        (lambda: stonedem.run_scenes([scene], device=None), "device: expected"),
        (lambda: stonedem.run_scene(scene, progress="no"), "progress: expected True or False"),
        (lambda: stonedem.run_wall(small_wall(), limit_analysis=1), "limit_analysis: expected"),
        (lambda: stonedem.load_scene(SCENE, base_dir=3), "base_dir: expected a folder path"),
    ):
        with pytest.raises(TypeError, match=message):
            call()


def test_a_base_dir_that_is_not_a_folder_is_refused(tmp_path):
    """Was accepted: a file (or a missing folder) as base_dir, so a relative record was 'not
    found'; a name too long for the filesystem raised OSError (found by the API fuzz)."""
    for bad in (SCENE, tmp_path / "missing", "x" * 300, "a\x00b"):
        with pytest.raises(InputError, match=r"^base_dir: .* is not a folder; give the folder"):
            stonedem.load_scene(SCENE, base_dir=bad)
    assert stonedem.load_scene(SCENE, base_dir=tmp_path).duration > 0
