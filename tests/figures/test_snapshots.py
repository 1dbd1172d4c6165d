"""Snapshot strips and GIFs drawn from a case dataset alone (stonedem.figures.snapshots)."""

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from PIL import Image

from stonedem.engine import geometry
from stonedem.engine.run import run_scene
from stonedem.engine.scene import posed_vertices, scene_from_dict
from stonedem.errors import InputError
from stonedem.figures import snapshots
from stonedem.io.netcdf import write_dataset

ROCKING_BLOCK = Path(__file__).parents[1] / "data" / "scenes" / "rocking_block.yaml"
HARMONIC = {"kind": "harmonic", "frequency": 0.5, "amplitude": 0.25}
COLUMN = {  # collapses at about 2.5 s and the run stops there
    "name": "column-4-drums",
    "structure": {"kind": "column", "n_drums": 4, "height": 6.0, "width": 1.0},
    "excitation": HARMONIC,
    "solver": {"duration": 4.0},
    "output": {"every": 0.01},
}
COLONNADE = {  # stands through 3 s: 301 samples
    "name": "colonnade",
    "structure": {
        "kind": "colonnade",
        "n_columns": 3,
        "n_drums": 2,
        "clear_distance": 2.0,
        "epistyle_type": "a",
        "capital": {"height": 0.6, "width": 1.4},
    },
    "excitation": HARMONIC,
    "solver": {"duration": 3.0},
    "output": {"every": 0.01},
}


def simulated_case(spec, folder, name):
    """Run a scene, write its dataset like stonedem run does, read it back from the file."""
    path = write_dataset(run_scene(scene_from_dict(spec)), folder / f"{name}.nc")
    with xr.open_dataset(path) as ds:
        return path, ds.load()


@pytest.fixture(scope="module")
def column_case(tmp_path_factory):
    return simulated_case(COLUMN, tmp_path_factory.mktemp("column"), "column")


@pytest.fixture(scope="module")
def colonnade_case(tmp_path_factory):
    return simulated_case(COLONNADE, tmp_path_factory.mktemp("colonnade"), "colonnade")


def pose(ds, i):
    """x, y, theta of every body at sample i."""
    return tuple(ds[v].isel(time=i).values for v in ("x", "y", "theta"))


def shoelace_area(vertices):
    return abs(geometry.signed_area(vertices))


def test_polygons_from_dataset_have_the_scene_areas(colonnade_case):
    _, ds = colonnade_case
    polygons = snapshots.body_polygons(ds)
    assert len(polygons) == ds.sizes["body"]
    # by hand: columns 3 m apart (1 m shafts, 2 m clear), capitals 1.4 m wide, so the type a
    # epistyle spans 7.4 m and the base 7.4 + 2 x 2 m margin; base 0.5 m, epistyle 0.8 m high
    expected = 11.4 * 0.5 + 3 * 6.0 * 1.0 + 3 * 0.6 * 1.4 + 7.4 * 0.8
    total = sum(shoelace_area(p) for p in polygons)
    assert abs(total - expected) < 1e-9 * expected, f"total area {total} m2, scene {expected} m2"
    # each stone body: its mass over density x depth (2000 kg/m3, 1 m)
    bodies = zip(ds.body.values, ds.body_role.values, ds.body_mass.values, polygons)
    for name, role, mass, poly in bodies:
        if role != "base":
            area, drawn = mass / 2000.0, shoelace_area(poly)
            assert abs(drawn - area) < 1e-9 * area, f"{name}: {drawn} m2, scene {area} m2"


def test_posed_polygon_centroid_is_the_body_position(column_case):
    _, ds = column_case
    local = snapshots.body_polygons(ds)
    i = int(np.abs(ds.theta.values).max(axis=1).argmax())  # the most rotated pose of the run
    x, y, theta = pose(ds, i)
    assert np.abs(theta).max() > 1e-3, "the pose should include a rotation"
    for k, poly in enumerate(snapshots.posed_polygons(local, x, y, theta)):
        centroid = geometry.centroid(poly)
        assert np.abs(centroid - [x[k], y[k]]).max() < 1e-9, f"{ds.body.values[k]}: {centroid}"


def test_pose_at_t0_is_the_tilted_scene_outline(tmp_path):
    # the rocking block starts leaning clockwise onto its right corner: checks the sense of theta
    spec = yaml.safe_load(open(ROCKING_BLOCK))
    spec["solver"]["duration"] = 0.01
    _, ds = simulated_case(spec, tmp_path, "rocking")
    first = snapshots.posed_polygons(snapshots.body_polygons(ds), *pose(ds, 0))
    for body, poly in zip(scene_from_dict(spec).bodies, first):
        expected = posed_vertices(body)
        assert np.abs(poly - expected).max() < 1e-9, f"{body.name}: {poly} vs {expected}"


def test_default_panels_end_at_the_collapse(column_case):
    _, ds = column_case
    assert int(ds.collapsed) == 1
    samples = snapshots.snapshot_samples(ds, n=5)
    times = ds.time.values[samples]
    assert len(samples) == 5 and times[0] == 0.0
    assert times[-1] == pytest.approx(float(ds.collapse_time), abs=1e-12)
    with pytest.raises(InputError, match="--times"):
        snapshots.snapshot_samples(ds, times=[0.0, 99.0])


def test_strip_png_is_written(column_case, tmp_path):
    _, ds = column_case
    out = snapshots.snapshot_strip(ds, tmp_path / "strip.png", n=4)
    with Image.open(out) as im:
        assert im.format == "PNG"
        width, height = im.size
        assert width > 2 * height, "one row of panels"
        pixels = np.asarray(im.convert("RGB")).reshape(-1, 3)
    stone = np.array([0xE3, 0xD3, 0xB0])
    stone_pixels = (np.abs(pixels.astype(int) - stone).sum(axis=1) < 6).sum()
    assert stone_pixels > 1000, "drums drawn in stone colour"
    assert [p.name for p in tmp_path.iterdir()] == ["strip.png"], "no temporary file left"


def test_gif_has_the_expected_frames(colonnade_case, tmp_path):
    _, ds = colonnade_case
    assert ds.sizes["time"] == 301
    # at most 31 frames of 301 samples: every 10th sample, 0 to 300
    out = snapshots.animate(ds, tmp_path / "movie.gif", fps=10, max_frames=31, progress=False)
    with Image.open(out) as im:
        assert im.format == "GIF" and im.n_frames == 31
        assert im.info["duration"] == 100, "10 frames per second"
    # a frame every 0.5 s of simulated time: 0, 0.5, ..., 3 s
    out = snapshots.animate(ds, tmp_path / "coarse.gif", every=0.5, progress=False)
    with Image.open(out) as im:
        assert im.n_frames == 7


def test_frame_samples_keep_the_last_sample_and_the_cap():
    for n_time in (1, 2, 7, 250, 301, 1000):
        for cap in (1, 2, 5, 31, 300):
            frames = snapshots.frame_samples(n_time, cap)
            assert 1 <= len(frames) <= cap and frames[0] == 0
            assert frames[-1] == n_time - 1 or cap == 1
            assert np.all(np.diff(frames) > 0)


def test_cli_writes_beside_the_case(column_case, tmp_path):
    src, _ = column_case
    case = tmp_path / "case.nc"
    case.write_bytes(src.read_bytes())
    assert snapshots.main(["snapshots", str(case), "--times", "0", "1", "2"]) == 0
    assert (tmp_path / "case_snapshots.png").is_file()
    assert snapshots.main_animate([str(case), "--max-frames", "5"]) == 0
    with Image.open(tmp_path / "case.gif") as im:
        assert im.n_frames == 5


def test_cli_bad_input_exits_2_and_writes_nothing(column_case, tmp_path, capsys):
    src, ds = column_case
    not_dem = tmp_path / "other.nc"
    xr.Dataset({"t": ("time", np.zeros(3))}).to_netcdf(not_dem)
    no_scene = tmp_path / "no_scene.nc"
    stripped = ds.copy()
    stripped.attrs = {}
    stripped.to_netcdf(no_scene)
    cases = [
        (["animate", str(tmp_path / "missing.nc")], "not found"),
        (["animate", str(not_dem), "-o", str(tmp_path / "out.gif")], "x: missing"),
        (["snapshots", str(no_scene), "-o", str(tmp_path / "out.png")], "attrs.scene"),
        (["snapshots", str(src), "-o", str(tmp_path / "out.png"), "--times", "50"], "--times"),
        (["animate", str(src), "-o", str(tmp_path / "out.mp4")], ".gif"),
        # a bare ".gif" said "'.gif' does not end in .gif"
        (["animate", str(src), "-o", str(tmp_path / ".gif")], "has no name before .gif"),
    ]
    before = sorted(tmp_path.iterdir())
    for argv, field in cases:
        assert snapshots.main(argv) == 2, argv
        lines = capsys.readouterr().err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("error: ") and field in lines[0], lines
        assert sorted(tmp_path.iterdir()) == before, f"{argv} left a file behind"


# --- hostile input: refused in one line, exit 2, nothing created (stonedem.cli.main) --------


def tree(folder):
    """Every path under folder, so a test sees a stray file or folder anywhere below it."""
    return sorted(str(p.relative_to(folder)) for p in Path(folder).rglob("*"))


def refused(argv, field, folder, capsys):
    """stonedem argv exits 2 with one 'error:' line naming field, and leaves folder as it was."""
    from stonedem.cli import main as cli_main

    before = tree(folder)
    try:
        status = cli_main(argv)
    except SystemExit as stop:  # a usage error of the parser
        status = stop.code
    lines = capsys.readouterr().err.strip().splitlines()
    assert status == 2, (argv, lines)
    assert len(lines) == 1 and lines[0].startswith("error: ") and field in lines[0], (argv, lines)
    assert "Traceback" not in lines[0]
    assert tree(folder) == before, f"{argv} created {set(tree(folder)) - set(before)}"
    return lines[0]


@pytest.fixture(scope="module")
def hostile_cases(column_case, tmp_path_factory):
    """{name: path} of damaged or foreign files, each made from the column case."""
    _, ds = column_case
    folder = tmp_path_factory.mktemp("hostile")
    made = {}

    def save(name, d):
        made[name] = folder / f"{name}.nc"
        d.to_netcdf(made[name])

    def with_scene(text):
        d = ds.copy()
        d.attrs = {**ds.attrs, "scene": text}
        return d

    save("scene_list", with_scene("[1, 2]"))
    save("scene_yaml", with_scene("structure: {kind: column\nn_drums: [4"))
    save("scene_number", with_scene(np.array([1.0, 2.0])))
    save("scene_string", with_scene('"a column"'))
    for name, value in (("x_nan", np.nan), ("theta_inf", np.inf), ("y_huge", 1e300)):
        var = name.split("_")[0]
        d = ds.copy()
        values = d[var].values.copy()
        values[10, 2] = value
        d[var] = (d[var].dims, values)
        save(name, d)
    save("extra_dim", ds.assign(theta=ds.theta.expand_dims(extra=2)))
    save("base_2d", ds.assign(base_displacement=ds.base_displacement.expand_dims(extra=2)))
    save("collapsed_nan", ds.assign(collapsed=np.nan))
    save("x_text", ds.assign(x=ds.x.astype(str)))
    save(
        "time_flat",
        ds.assign_coords(time=np.where(np.arange(ds.sizes["time"]) == 5, ds.time[4], ds.time)),
    )
    for var in ("x", "theta", "body_role"):
        save(f"no_{var}", ds.drop_vars(var))
    save("other_bodies", ds.assign_coords(body=[f"b{i}" for i in range(ds.sizes["body"])]))
    (folder / "text.nc").write_text("time,x\n0,1\n")
    (folder / "empty.nc").write_bytes(b"")
    (folder / "png.nc").write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(100))
    (folder / "folder.nc").mkdir()
    made.update({k: folder / f"{k}.nc" for k in ("text", "empty", "png", "folder")})
    return made


@pytest.mark.parametrize(
    "name, field",
    [
        ("scene_list", "attrs.scene: JSON list, not a mapping"),
        ("scene_yaml", "attrs.scene: not valid JSON"),
        ("scene_number", "attrs.scene"),
        ("scene_string", "attrs.scene: JSON str, not a mapping"),
        ("x_nan", "x: 1 non-finite"),
        ("theta_inf", "theta: 1 non-finite"),
        ("y_huge", "y: holds values beyond"),
        ("extra_dim", "theta: has dimensions"),
        ("base_2d", "base_displacement: has dimensions"),
        ("collapsed_nan", "collapsed"),
        ("x_text", "x: holds"),
        ("time_flat", "time: is not increasing"),
        ("no_x", "x: missing"),
        ("no_theta", "theta: missing"),
        ("no_body_role", "body_role: missing"),
        ("other_bodies", "body"),
        ("text", "not a readable NetCDF"),
        ("empty", "not a readable NetCDF"),
        ("png", "not a readable NetCDF"),
        ("folder", "is a folder"),
    ],
)
@pytest.mark.parametrize("command", ["snapshots", "animate"])
def test_hostile_dataset_is_refused_before_drawing(
    hostile_cases, tmp_path, capsys, name, field, command
):
    out = tmp_path / "new" / ("out.png" if command == "snapshots" else "out.gif")
    refused([command, str(hostile_cases[name]), "-o", str(out)], field, tmp_path, capsys)
    assert not (tmp_path / "new").exists(), "no folder made for a refused picture"


@pytest.mark.parametrize(
    "options, field",
    [
        (["--fps", "1e-9"], "--fps"),
        (["--fps", "0"], "--fps"),
        (["--fps", "-5"], "--fps"),
        (["--fps", "nan"], "--fps"),
        (["--fps", "inf"], "--fps"),
        (["--fps", "1e9"], "--fps"),
        (["--every", "inf"], "--every"),
        (["--every", "nan"], "--every"),
        (["--every", "-1"], "--every"),
        (["--every", "0"], "--every"),
        (["--every", "1e300"], "--every"),
        (["--every", "100"], "--every"),
        (["--max-frames", "0"], "--max-frames"),
        (["--max-frames", "1000000000"], "--max-frames"),
        (["--max-frames", "1.5"], "--max-frames"),
        (["--title", "a\x1b[31mred"], "--title"),
        (["--title", "x" * 1000], "--title"),
    ],
)
def test_animate_options_have_ranges(column_case, tmp_path, capsys, options, field):
    src, _ = column_case
    refused(
        ["animate", str(src), "-o", str(tmp_path / "a" / "b.gif"), *options],
        field,
        tmp_path,
        capsys,
    )


@pytest.mark.parametrize(
    "options, field",
    [
        (["-n", "0"], "-n"),
        (["-n", "-3"], "-n"),
        (["-n", "1000000"], "-n"),
        (["-n", str(snapshots.MAX_PANELS + 1)], "-n"),
        (["-n", "1e6"], "-n"),
        (["--times", "nan"], "--times"),
        (["--times", "0", "inf"], "--times"),
        (["--times", *["0.1"] * (snapshots.MAX_PANELS + 1)], "--times"),
        (["--times", "-1"], "--times"),
        (["--title", "two\nlines"], "--title"),
    ],
)
def test_snapshot_options_have_ranges(column_case, tmp_path, capsys, options, field):
    src, _ = column_case
    refused(
        ["snapshots", str(src), "-o", str(tmp_path / "a" / "b.png"), *options],
        field,
        tmp_path,
        capsys,
    )


def test_n_has_a_stated_upper_bound(capsys):
    from stonedem.cli import main as cli_main

    with pytest.raises(SystemExit):
        cli_main(["snapshots", "--help"])
    assert f"1 to {snapshots.MAX_PANELS}" in capsys.readouterr().out


def test_output_in_an_unwritable_place_is_refused_first(column_case, tmp_path, capsys):
    src, _ = column_case
    refused(["snapshots", str(src), "-o", "/proc/stonedem/x.png"], "-o", tmp_path, capsys)
    refused(["animate", str(src), "-o", "/proc/x.gif"], "-o", tmp_path, capsys)
    blocker = tmp_path / "file"
    blocker.write_text("")
    refused(
        ["snapshots", str(src), "-o", str(blocker / "x.png")],
        "is a file, not a folder",
        tmp_path,
        capsys,
    )
    # a bad option with an output in a folder that does not exist yet: no folder is made
    refused(
        ["snapshots", str(src), "-o", str(tmp_path / "d" / "e" / "x.png"), "--times", "99"],
        "--times",
        tmp_path,
        capsys,
    )


def test_dollar_titles_are_plain_text(column_case, tmp_path, capsys):
    from stonedem.cli import main as cli_main

    src, ds = column_case
    bad_tex = r"a $\frac{$ b $x^$ 100%"
    out = tmp_path / "title.png"
    assert cli_main(["snapshots", str(src), "-o", str(out), "-n", "2", "--title", bad_tex]) == 0
    assert out.is_file()
    # a scene named with TeX, drawn with the default title; a GIF too
    spec = json.loads(ds.attrs["scene"])
    spec["name"] = r"$\undefinedcommand{$"
    named = ds.copy()
    named.attrs = {**ds.attrs, "scene": json.dumps(spec)}
    assert "$" in snapshots.default_title(named)
    case = tmp_path / "named.nc"
    named.to_netcdf(case)
    assert (
        cli_main(["animate", str(case), "-o", str(tmp_path / "named.gif"), "--max-frames", "2"])
        == 0
    )
    capsys.readouterr()


def test_default_title_survives_a_foreign_excitation(column_case):
    _, ds = column_case
    odd = ds.copy()
    odd.attrs = {**ds.attrs, "excitation": json.dumps({"kind": [1], "pga": "x"})}
    assert "base motion unknown" in snapshots.default_title(odd)
