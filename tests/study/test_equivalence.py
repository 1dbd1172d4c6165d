"""Judging a changed engine against the stored baseline ensemble (python -m
stonedem.study.equivalence, issue 44): hand-built ensemble files in the layout of
stonedem.study.ensemble, K_B = 8 and K_N = 4 members drawn from one Bernoulli (verdicts) and
lognormal (thresholds) model."""

import numpy as np
import pytest
import xarray as xr

from stonedem.study.equivalence import judge, main

N_CASES, N_SYSTEMS, N_CHECKS, N_SCENES = 40, 6, 5, 2
TOLERANCE = 0.02
SPREAD = 0.02  # sd of ln threshold over members: about one search bracket


def _ensemble(
    members, seed, threshold_factor=1.0, source="stonedem 0.1.0 (aaaaaaa)", check_shift=0.0
):
    """An ensemble file's dataset: verdicts Bernoulli(p_c), p_c fixed (most cases unanimous, a
    few split), thresholds lognormal about fixed medians, on the search's 4-digit grid."""
    model = np.random.default_rng(44)
    p = np.concatenate([np.zeros(15), np.ones(15), model.uniform(0.2, 0.8, N_CASES - 30)])
    median = model.uniform(2.0, 8.0, N_SYSTEMS)
    rng = np.random.default_rng(seed)
    k = len(members)
    collapsed = (rng.random((N_CASES, k)) < p[:, None]).astype(np.int8)
    threshold = np.round(
        median[:, None] * threshold_factor * np.exp(SPREAD * rng.standard_normal((N_SYSTEMS, k))), 3
    )
    check_value = np.linspace(1.0, 5.0, N_CHECKS) * (1.0 + 1e-13 * rng.standard_normal(N_CHECKS))
    check_value[0] *= 1.0 + check_shift
    reference = np.linspace(1.0, 5.0, N_CHECKS) * 1.001
    time = np.linspace(0.0, 0.5, 51)
    trajectory = np.stack(
        [
            np.stack([0.01 * np.sin(3 * time + s), 0.5 + 0 * time, 0.02 * np.sin(5 * time)], axis=1)
            for s in range(N_SCENES)
        ]
    )
    trajectory = trajectory + 1e-14 * rng.standard_normal(trajectory.shape)
    cases = [f"s/c{i:02d}" for i in range(N_CASES)]
    return xr.Dataset(
        {
            "collapsed": (
                ("case", "member"),
                collapsed,
                {"units": "1", "long_name": "collapse verdict"},
            ),
            "max_rocking": (
                ("case", "member"),
                rng.random((N_CASES, k)),
                {"units": "rad", "long_name": "peak"},
            ),
            "threshold": (
                ("system", "member"),
                threshold,
                {"units": "m s-2", "long_name": "threshold"},
            ),
            "check_value": ("check", check_value, {"units": "1", "long_name": "value"}),
            "check_reference": ("check", reference, {"units": "1", "long_name": "reference"}),
            "check_error": (
                "check",
                np.abs(check_value / reference - 1.0),
                {"units": "1", "long_name": "error"},
            ),
            "check_tolerance": (
                "check",
                np.full(N_CHECKS, 0.01),
                {"units": "1", "long_name": "tolerance"},
            ),
            "check_passes": (
                "check",
                np.ones(N_CHECKS, np.int8),
                {"units": "1", "long_name": "passes"},
            ),
            "trajectory": (
                ("scene", "sample", "coordinate"),
                trajectory,
                {"units": "1", "long_name": "x, y, theta"},
            ),
            "coordinate_kind": (
                ("scene", "coordinate"),
                np.tile(np.array([0, 0, 1], np.int8), (N_SCENES, 1)),
                {"units": "1", "long_name": "0 position, 1 rotation"},
            ),
            "floor_position": (
                "scene",
                np.full(N_SCENES, 1e-12),
                {"units": "m", "long_name": "last-bit floor"},
            ),
            "floor_rotation": (
                "scene",
                np.full(N_SCENES, 1e-12),
                {"units": "rad", "long_name": "last-bit floor"},
            ),
        },
        coords={
            "member": ("member", np.array(members, np.int32), {"units": "1"}),
            "case": ("case", cases),
            "case_study": ("case", ["s"] * N_CASES),
            "system": ("system", [f"s/t{i}" for i in range(N_SYSTEMS)]),
            "search_parameter": ("system", ["pga"] * N_SYSTEMS),
            "search_tolerance": ("system", np.full(N_SYSTEMS, TOLERANCE)),
            "search_maximum": ("system", np.full(N_SYSTEMS, 20.0)),
            "check": ("check", [f"check_{i}" for i in range(N_CHECKS)]),
            "scene": ("scene", [f"scene_{i}" for i in range(N_SCENES)]),
        },
        attrs={
            "members": k,
            "first_member": int(members[0]),
            "perturbation": "stiffness",
            "source": source,
            "machine": "test",
            "config": "config/config.yaml",
        },
    )


def _write(ds, path):
    ds.to_netcdf(path, engine="netcdf4")
    return path


@pytest.fixture
def files(tmp_path):
    """(baseline.nc, candidate.nc, output path): the baseline K = 8 (j = 0..7), the candidate
    K = 4 (j = 0..3) of other code (another source commit), both from the same model."""
    base = _write(_ensemble(range(8), seed=1), tmp_path / "baseline.nc")
    cand = _write(
        _ensemble(range(4), seed=2, source="stonedem 0.1.0 (bbbbbbb)"), tmp_path / "candidate.nc"
    )
    return base, cand, tmp_path / "out" / "equivalence.nc"


def _run(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out.splitlines(), err.splitlines()


def test_a_candidate_from_the_same_model_is_equivalent(files, capsys):
    base, cand, out = files
    code, lines, err = _run(capsys, base, cand, "--out", out)
    assert code == 0, (lines, err)
    assert lines[0].startswith("A exact checks: pass (5 checks, worst ")
    assert lines[1].startswith("B short horizon: pass (2 scenes, worst ")
    assert lines[2].startswith("C ensemble: pass (S_v ") and lines[2].endswith(
        "; 495 assignments, exact)"
    )
    assert lines[-1] == "equivalent: yes"
    with xr.open_dataset(out) as ds:
        assert ds.attrs["equivalent"] == "yes" and ds.attrs["baseline_members"] == 8
        assert ds.attrs["candidate_members"] == 4 and ds.attrs["candidate_file"] == str(cand)
        assert list(ds.verdict.values) == ["pass", "pass", "pass", "not requested"]
        assert int(ds.n_assignments) == 495 == int(ds.exact) * 495  # C(12, 4), every one
        assert float(ds.p_v) > 0.05 and float(ds.p_t) > 0.05
        assert float(ds.threshold_shift.sum()) == pytest.approx(
            float(ds.s_t), rel=1e-12
        )  # S_T's own terms
        for name, var in ds.variables.items():
            assert "long_name" in var.attrs, name
            assert var.dtype.kind not in "fi" or "units" in var.attrs, name


def test_every_threshold_10_percent_higher_fails_the_ensemble_test(files, tmp_path, capsys):
    base, _, out = files
    cand = _write(
        _ensemble(range(4), seed=2, threshold_factor=1.10, source="new"), tmp_path / "higher.nc"
    )
    code, lines, _ = _run(capsys, base, cand, "--out", out)
    assert code == 1 and lines[-1] == "equivalent: no"
    assert lines[2].startswith("C ensemble: fail (")
    with xr.open_dataset(out) as ds:
        # 1 + 0 of 495 assignments reach the observed S_T: p = 2 / 496 at most
        assert float(ds.p_t) <= 0.005 and float(ds.p_v) > 0.005
        # ln 1.10 / ln 1.02 = 4.8 brackets per system, less the members' scatter
        assert np.all(ds.threshold_shift.values > 3.0)


def test_a_check_moved_by_1e_6_fails_layer_a(files, tmp_path, capsys):
    base, _, out = files
    cand = _write(
        _ensemble(range(4), seed=2, check_shift=1e-6, source="new"), tmp_path / "moved.nc"
    )
    code, lines, _ = _run(capsys, base, cand, "--out", out)
    assert (
        code == 1
        and lines[0].startswith("A exact checks: fail (")
        and lines[1].startswith("B short horizon: pass")
    )
    assert lines[2].startswith("C ensemble: pass")


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda p: p.write_text("not a dataset\n"), "is not a NetCDF file"),
        (
            lambda p: xr.Dataset({"x": ("i", [1.0])}).to_netcdf(p, engine="netcdf4"),
            "has no dimension 'member'",
        ),
        (
            lambda p: _ensemble(range(4), 2).drop_vars("collapsed").to_netcdf(p, engine="netcdf4"),
            "has a 'case' dimension but no collapsed",
        ),
    ],
)
def test_a_file_of_the_wrong_kind_is_one_line_exit_2_and_no_output(
    files, tmp_path, capsys, make, message
):
    base, _, out = files
    bad = tmp_path / "bad.nc"
    make(bad)
    code, lines, err = _run(capsys, base, bad, "--out", out)
    assert (code, lines, len(err)) == (2, [], 1)
    assert err[0].startswith("error: CANDIDATE: ") and message in err[0]
    assert not out.parent.exists()


def test_another_case_set_is_refused_naming_one_case_and_the_config(files, tmp_path, capsys):
    base, _, out = files
    other = _ensemble(range(4), seed=2, source="new")
    other = other.assign_coords(case=[*other.case.values[:-1], "s/elsewhere"])
    code, lines, err = _run(capsys, base, _write(other, tmp_path / "other.nc"), "--out", out)
    assert (code, lines, len(err)) == (2, [], 1)
    assert "'s/c39' is in the baseline only" in err[0]
    assert "run it with the baseline's config, attrs `config` (config/config.yaml)" in err[0]
    assert not out.parent.exists()


def test_one_candidate_member_is_refused_for_layer_c_only(files, tmp_path, capsys):
    base, _, out = files
    single = _write(_ensemble([0], seed=2, source="new"), tmp_path / "single.nc")
    code, _, err = _run(capsys, base, single, "--out", out)
    assert code == 2 and "needs at least 2 in each file" in err[0] and "--layers A B" in err[0]
    code, lines, _ = _run(capsys, base, single, "--layers", "A", "B", "--out", out)
    assert code == 0 and lines == [lines[0], lines[1], "equivalent: yes"]


def test_too_few_members_for_p_to_reach_alpha_are_refused(tmp_path, capsys):
    """5 + 3 members: C(8, 3) = 56 assignments, p >= 1/56 > 0.005: a layer C that cannot fail."""
    base = _write(_ensemble(range(5), seed=1), tmp_path / "five.nc")
    cand = _write(_ensemble(range(3), seed=2, source="new"), tmp_path / "three.nc")
    code, lines, err = _run(capsys, base, cand, "--out", tmp_path / "out.nc")
    assert (code, lines, len(err)) == (2, [], 1)
    assert "5 + 3 members give 56 label assignments: p can never reach alpha 0.005" in err[0]
    assert not (tmp_path / "out.nc").exists()
    assert _run(capsys, base, cand, "--alpha", "0.05", "--out", tmp_path / "out.nc")[0] == 0


def test_a_layer_whose_data_are_missing_is_not_run_and_not_a_pass(files, tmp_path, capsys):
    base, _, out = files
    bare = _ensemble(range(4), seed=2, source="new").drop_dims(["check", "scene"])
    cand = _write(bare, tmp_path / "bare.nc")
    code, lines, _ = _run(capsys, base, cand, "--out", out)
    assert (
        code == 1
        and lines[0]
        == "A exact checks: not run (the candidate holds no check data (check_value, "
        "check_reference, check_passes))"
    )
    assert lines[-1] == "equivalent: no"
    assert _run(capsys, base, cand, "--layers", "C", "--out", out)[0] == 0


def test_same_source_and_shared_members_warn_but_do_not_fail(files, tmp_path, capsys):
    base, _, out = files
    cand = _write(_ensemble(range(4), seed=2), tmp_path / "same.nc")  # the baseline's source
    code, lines, _ = _run(capsys, base, cand, "--layers", "C", "--out", out)
    assert code == 0 and any(
        line.startswith(
            "warning: both files come from stonedem 0.1.0 (aaaaaaa) and share members j = 0..3"
        )
        for line in lines
    )


def test_members_perturbed_another_way_than_the_baseline_s_warn_but_do_not_fail(
    files, tmp_path, capsys
):
    base, _, out = files
    other = _ensemble(range(20, 24), seed=3, source="stonedem 0.1.0 (bbbbbbb)")
    other.attrs["perturbation"] = "geometry"
    cand = _write(other, tmp_path / "geometry.nc")
    code, lines, _ = _run(capsys, base, cand, "--layers", "C", "--out", out)
    assert code == 0 and any(
        line.startswith(
            "warning: the baseline's members are perturbed by stiffness, the "
            "candidate's by geometry"
        )
        for line in lines
    )


def test_fragility_fits_within_and_beyond_the_shift_tolerance():
    def with_fits(ds, theta, beta):
        fits = {
            "fit_theta": ("fit", np.array(theta), {"units": "m s-2", "long_name": "median"}),
            "fit_beta": ("fit", np.array(beta), {"units": "1", "long_name": "dispersion"}),
            "fit_n": ("fit", np.array([100, 25]), {"units": "1", "long_name": "records"}),
        }
        return ds.assign(fits).assign_coords(fit=["a", "b"])

    base = with_fits(_ensemble(range(8), 1), [3.0, 3.0], [0.40, 0.40])
    # tolerances 0.02 (n = 100) and 0.04 (n = 25): a 1.9 % and a 3.9 % move pass
    near = with_fits(
        _ensemble(range(4), 2, source="new"),
        [3.0 * np.exp(0.019), 3.0 * np.exp(0.039)],
        [0.41, 0.43],
    )
    far = with_fits(_ensemble(range(4), 2, source="new"), [3.0, 3.0], [0.40, 0.445])
    assert list(judge(base, near).verdict.values) == ["pass"] * 4
    judged = judge(base, far, layers=["F"])
    assert list(judged.verdict.values) == ["not requested"] * 3 + ["fail"]
    assert list(judged.fit_passes.values) == [
        1,
        0,
    ] and judged.fit_tolerance.values == pytest.approx([0.02, 0.04])


def test_a_failed_write_leaves_the_earlier_result_whole(files, capsys, monkeypatch):
    base, cand, out = files
    assert _run(capsys, base, cand, "--layers", "C", "--out", out)[0] == 0
    before = out.read_bytes()

    def broken(self, path, *args, **kwargs):
        with open(path, "wb") as handle:
            handle.write(b"CDF\x01 half a file")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", broken)
    code, lines, err = _run(capsys, base, cand, "--out", out)
    assert (code, lines, len(err)) == (2, [], 1) and "No space left on device" in err[0]
    assert out.read_bytes() == before and sorted(p.name for p in out.parent.iterdir()) == [out.name]
