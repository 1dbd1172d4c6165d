"""Does the equivalence test work? Its false-alarm rate and power, measured (issue 44, item 6;
../shared/research/ENSEMBLES.md, section 4; docs/method/equivalence.md).

Every draw is a K_N = 4 candidate ensemble (:mod:`stonedem.study.ensemble`) judged against the
stored baseline by :func:`stonedem.study.equivalence.judge`:

- ``null``: the unchanged code with fresh members, draw d: j = J + 4d .. J + 4d + 3 (J: one past
  the baseline's last member), with layers A and B of member J + 4d (the unchanged code differs
  from the baseline by its perturbation only). Its rejections are false alarms (target <= 2 %).
- ``shift``: the same members with every base acceleration, velocity and displacement x 1.02
  inside the study's runs (so every threshold moves by 1/1.02, 2 %); layer C (target power >= 70 %).
- ``flips``: null draw d's data with three grid verdicts flipped in every candidate member,
  among the cases every baseline member agrees on (seeded choice); layer C, no runs (>= 95 %).
- ``friction``: one draw with every friction coefficient x 1.01 in the study's runs; layer C
  (reported, no target).
- ``edge_normal``: one draw of HEAD with issue 32's body-frame edge normals put back
  (equivalence_calibration_edge_normals.patch beside this script: 534605d, reverted by ba4d380,
  on the kernels of 2026-11-29; the draw in calibration.nc was made with the first version,
  74b7bca), run in a git worktree under /tmp; every layer the baseline has (reported).
- ``tilt``: one draw of the unchanged code with the second perturbation (members lean by
  +-1e-6 rad, :mod:`stonedem.study.members`); layer C (reported: does the k_n baseline's band
  hold the tilt members, item 1's check that the band is complete).

The shift and the friction change act on the scene each worker builds (:data:`CHANGE_VARIABLE`,
read when this script is imported: the runner's spawned workers import it again, so the pool
sees the change); the library's physics has no switch for them.

Resumable: each draw's candidate is its own file in ``--work`` (written whole or not at all),
reused when it is there and matches the baseline, draw and members, so the ~2.5 h of a full
calibration can be spread over sessions (``--draws``, ``--only``). The judgements are remade
every time (seconds). Writes ``--out`` (calibration.nc: one row per draw, the rates in attrs).

The draws' rates bound small rates loosely (0 rejections in 10 draws: <= 31 % at 95 %), so the
script also resamples the runs on disk (:func:`resampled_rates`, ``--resamples``): candidates of
4 runs picked again and again from the fresh null and shift members, judged by layer C alone
(layers A and B of the unchanged code agree with the baseline exactly, so a null draw's false
alarms are layer C's).

    python -m benchmarks.equivalence_calibration --baseline
    benchmarks/ensemble/2026-11-28/ensemble.nc
        [--config CONFIG] [--draws 10] [--only null shift flips friction edge_normal tilt] [--jobs
        2] [--work results/bench/calibration] [--out results/bench/calibration/calibration.nc]
"""

from __future__ import annotations

import dataclasses
import math
import os
import subprocess
import sys
import time
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np
import xarray as xr

from benchmarks import options
from stonedem.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
KINDS = ("null", "shift", "flips", "friction", "edge_normal", "tilt")
SINGLE = ("friction", "edge_normal", "tilt")  # kinds of one draw (report only)
MEMBERS = 4  # K_N of every candidate (ENSEMBLES.md section 4)
SHIFT = 1.02  # base motion factor: every threshold moves by 2 %
FRICTION = 1.01  # friction factor of the report-only draw
N_FLIPS = 3  # verdicts flipped per flips draw
TARGETS = {"false_alarm_rate": 0.02, "power_shift": 0.70, "power_flips": 0.95}  # issue 44, item 6
WORK = Path("results/bench/calibration")
PATCH = Path(__file__).resolve().with_name("equivalence_calibration_edge_normals.patch")
CHANGE_VARIABLE = "STONEDEM_CALIBRATION_CHANGE"  # "motion=1.02" or "friction=1.01": the hook below
CONFIDENCE = 0.95
RESAMPLES = 1000  # random picks of runs on disk per resampled rate
RESAMPLE_PERMUTATIONS = 4000  # layer C's assignments per resample (p resolves 1/4001 << alpha)
LAYER_B_SECONDS = 0.5  # [s] the runner's layer B horizon (stonedem.study.ensemble.ensemble_dataset)


# --- the change, in the scene every worker builds -------------------------------------------


def scaled_motion(motion, factor: float):
    """A BaseMotion x ``factor``: displacement, velocity and acceleration (every kind is linear
    in params[0], a table in its three columns: stonedem.kernels.excitation.base_motion)."""
    from stonedem.kernels import excitation as kx

    if motion.kind == kx.KIND_NONE:
        return motion
    if motion.kind == kx.KIND_TABLE:
        return dataclasses.replace(
            motion,
            table_accel=motion.table_accel * factor,
            table_vel=motion.table_vel * factor,
            table_disp=motion.table_disp * factor,
        )
    params = motion.params.copy()
    params[0] *= factor  # amplitude, pulse height or ramp rate
    return dataclasses.replace(motion, params=params)


def changed_scene(scene, change: dict):
    """``scene`` with the calibration's change: {"motion": f} scales both base motions by f,
    {"friction": f} every friction coefficient (the scene's, each body's, each pair's)."""
    if "motion" in change:
        f = change["motion"]
        scene = dataclasses.replace(
            scene,
            horizontal=scaled_motion(scene.horizontal, f),
            vertical=scaled_motion(scene.vertical, f),
        )
    if "friction" in change:
        f = change["friction"]
        bodies = tuple(
            b if b.friction is None else dataclasses.replace(b, friction=b.friction * f)
            for b in scene.bodies
        )
        scene = dataclasses.replace(
            scene,
            friction=scene.friction * f,
            bodies=bodies,
            pair_friction={k: v * f for k, v in scene.pair_friction.items()},
        )
    return scene


def parse_change(text: str) -> dict:
    """{"motion" | "friction": factor} of a CHANGE_VARIABLE value ("" or unset: {})."""
    change = {}
    for item in filter(None, (text or "").split(",")):
        key, _, value = item.partition("=")
        if key not in ("motion", "friction"):
            raise InputError(
                CHANGE_VARIABLE, f"unknown change {key!r}", "give motion=F or friction=F"
            )
        change[key] = float(value)
    return change


_PLAIN_MEMBER_SCENE = None


def install_change(change: dict) -> None:
    """Make :mod:`stonedem.study.ensemble` build every member's scene with ``change`` ({}:
    as configured again). Its member_verdict and member_value call its member_scene."""
    global _PLAIN_MEMBER_SCENE
    from stonedem.study import ensemble

    if _PLAIN_MEMBER_SCENE is None:
        _PLAIN_MEMBER_SCENE = ensemble.member_scene
    plain = _PLAIN_MEMBER_SCENE
    if not change:
        ensemble.member_scene = plain
        return

    def member_scene(scene, j, perturbation="stiffness"):
        return changed_scene(plain(scene, j, perturbation), change)

    ensemble.member_scene = member_scene


if os.environ.get(CHANGE_VARIABLE):  # this process is a worker of a shift or friction draw
    install_change(parse_change(os.environ[CHANGE_VARIABLE]))


# --- draws -------------------------------------------------------------------------------------


def draw_members(first_fresh: int, d: int) -> list[int]:
    """Members j of draw d: J + 4d .. J + 4d + 3, J one past the baseline's last member."""
    return list(range(first_fresh + MEMBERS * d, first_fresh + MEMBERS * (d + 1)))


def candidate_path(work: Path, kind: str, d: int) -> Path:
    return work / f"candidate-{kind}-{d:02d}.nc"


def usable_draw(path: Path, kind: str, d: int, members: list[int], baseline: xr.Dataset) -> bool:
    """An earlier draw's file to reuse: readable, of this kind, draw, members and baseline."""
    if not path.is_file():
        return False
    try:
        with xr.open_dataset(path) as ds:
            attrs, found = dict(ds.attrs), [int(j) for j in ds.member.values]
    except (KeyboardInterrupt, MemoryError):
        raise
    except Exception:  # noqa: BLE001 - a damaged or foreign file is made again
        return False
    return (
        attrs.get("calibration_kind") == kind
        and int(attrs.get("calibration_draw", -1)) == d
        and found == members
        and attrs.get("calibration_baseline") == baseline_key(baseline)
    )


def baseline_key(baseline: xr.Dataset) -> str:
    """What identifies the baseline a draw was made for: its config digest and members."""
    return f"{baseline.attrs.get('config_digest', '?')} members {baseline.sizes['member']}"


def make_candidate(plan: dict, kind: str, d: int, members: list[int], path: Path) -> float:
    """Run draw d of ``kind`` (members ``members``) in this process's code and write its
    candidate file; its wall seconds. Layers A and B (null and edge_normal draws, when the
    baseline has them) are member members[0]'s, without floors."""
    from stonedem.io.netcdf import write_dataset
    from stonedem.study import ensemble, exact_checks

    change = {"shift": {"motion": SHIFT}, "friction": {"friction": FRICTION}}.get(kind, {})
    start = time.perf_counter()
    os.environ[CHANGE_VARIABLE] = ",".join(f"{k}={v!r}" for k, v in change.items())  # the workers'
    install_change(change)  # this process's (--jobs 1)
    try:
        results = ensemble.run_members(
            plan["cases"],
            plan["systems"],
            members,
            plan["jobs"],
            perturbation="tilt" if kind == "tilt" else "stiffness",
            label=f"{kind} {d} member",
        )
    finally:
        os.environ.pop(CHANGE_VARIABLE, None)
        install_change({})
    ds = ensemble.ensemble_dataset(
        plan["cases"],
        plan["systems"],
        results,
        "none",
        attrs={
            "config": plan["baseline"].attrs.get("config", ""),
            "config_digest": plan["baseline"].attrs.get("config_digest", ""),
            "command": f"benchmarks/equivalence_calibration.py, draw {kind} {d}",
        },
    )
    if kind in ("null", "edge_normal"):
        if "check" in plan["baseline"].dims:
            quick = plan["baseline"].attrs.get("checks") == "quick"
            ds = xr.merge(
                [ds, exact_checks.layer_a(quick=quick, floor_members=(), member=members[0])],
                combine_attrs="override",
            )
        if "scene" in plan["baseline"].dims:
            ds = xr.merge(
                [ds, exact_checks.layer_b(LAYER_B_SECONDS, floor_members=(), member=members[0])],
                combine_attrs="override",
            )
    wall = time.perf_counter() - start
    ds.attrs.update(
        calibration_kind=kind,
        calibration_draw=int(d),
        calibration_baseline=baseline_key(plan["baseline"]),
        calibration_change=", ".join(f"{k} x {v:g}" for k, v in change.items()) or "none",
        wall_seconds=wall,
        title=f"equivalence calibration: {kind} draw {d}, members {members[0]}..{members[-1]}",
    )
    write_dataset(ds, path)
    return wall


def edge_normal_tree(commit: str) -> Path:
    """A git worktree of ``commit`` under /tmp with :data:`PATCH` applied (made once, reused)."""
    tree = Path("/tmp") / f"stonedem-edge-normal-{commit[:10]}"
    git = ["git", "-C", str(ROOT)]
    if tree.is_dir():
        applied = (
            subprocess.run(
                ["git", "-C", str(tree), "apply", "--reverse", "--check", str(PATCH)],
                capture_output=True,
            ).returncode
            == 0
        )
        if applied:
            return tree
        subprocess.run([*git, "worktree", "remove", "--force", str(tree)], capture_output=True)
    subprocess.run(
        [*git, "worktree", "add", "--detach", str(tree), commit], check=True, capture_output=True
    )
    patched = subprocess.run(
        ["git", "-C", str(tree), "apply", str(PATCH)], capture_output=True, text=True
    )
    if patched.returncode != 0:
        why = (
            patched.stderr.strip().splitlines()[0] if patched.stderr.strip() else "git apply failed"
        )
        raise InputError(
            "--only edge_normal",
            f"{PATCH.name} does not apply to {commit[:10]} ({why})",
            "rebase the patch on the current kernels (git diff ba4d380 ba4d380^ -- src "
            "tests/kernels)",
        )
    return tree


def run_edge_normal(plan: dict, members: list[int], path: Path) -> float:
    """The edge_normal draw, made by this script in a child process on the patched worktree's
    code."""
    commit = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "HEAD"], check=True, capture_output=True, text=True
    ).stdout.strip()
    tree = edge_normal_tree(commit)
    env = dict(os.environ, PYTHONPATH=str(tree / "src"), XDG_CACHE_HOME=str(tree / ".cache"))
    env.pop("NUMBA_CACHE_DIR", None)  # the patched kernels compile into their own cache
    env.pop(CHANGE_VARIABLE, None)
    start = time.perf_counter()
    argv = [
        sys.executable,
        str(Path(__file__).resolve()),
        "--baseline",
        str(plan["baseline_path"]),
        "--config",
        str(plan["config"]),
        "--jobs",
        str(plan["jobs"]),
        "--work",
        str(plan["work"]),
        "--make-draw",
        "edge_normal",
        "--out",
        str(plan["out"]),
    ]
    status = subprocess.run(argv, cwd=ROOT, env=env).returncode
    if status != 0 or not path.is_file():
        raise InputError(
            "--only edge_normal",
            f"the patched worktree {tree} could not make the draw (exit {status})",
            "see the lines above; the patch may no longer fit the kernels",
        )
    return time.perf_counter() - start


def flipped(candidate: xr.Dataset, baseline: xr.Dataset, seed: int) -> tuple[xr.Dataset, list[str]]:
    """``candidate`` with N_FLIPS grid verdicts flipped in every member, chosen at random (``seed``)
    among the cases every baseline member agrees on: each to the opposite of the baseline's."""
    base = baseline.collapsed.transpose("case", "member").values
    unanimous = np.flatnonzero(base.min(axis=1) == base.max(axis=1))
    if unanimous.size < N_FLIPS:
        raise InputError(
            "--baseline",
            f"only {unanimous.size} grid cases every member agrees on",
            f"give a baseline with at least {N_FLIPS} such cases",
        )
    chosen = np.sort(np.random.default_rng(seed).choice(unanimous, N_FLIPS, replace=False))
    names = [str(baseline.case.values[k]) for k in chosen]
    out = candidate.copy(deep=True)
    for k, name in zip(chosen, names):
        out["collapsed"].loc[{"case": name}] = np.int8(1 - base[k, 0])
    return out, names


# --- the judgements ----------------------------------------------------------------------------


def judged(baseline, candidate, layers, seed: int, n_permutations: int) -> dict:
    """One draw's row: layer verdicts, the test's numbers, rejected or not."""
    from stonedem.study.equivalence import judge

    j = judge(baseline, candidate, layers=layers, n_permutations=n_permutations, seed=seed)
    verdict = dict(zip([str(v) for v in j.layer.values], [str(v) for v in j.verdict.values]))
    return {
        "verdict_a": verdict["A"],
        "verdict_b": verdict["B"],
        "verdict_c": verdict["C"],
        "rejected": int(j.attrs["equivalent"] != "yes"),
        **{k: float(j[k]) for k in ("p_v", "p_t", "s_v", "s_t")},
        "unanimous_flips": int(j.unanimous_flip.sum()) if "unanimous_flip" in j else 0,
    }


def binomial_interval(k: int, n: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """Clopper-Pearson interval of a rate k / n (exact, conservative)."""
    from scipy.stats import beta

    if n == 0:
        return math.nan, math.nan
    tail = (1.0 - confidence) / 2.0
    low = 0.0 if k == 0 else float(beta.ppf(tail, k, n - k + 1))
    high = 1.0 if k == n else float(beta.ppf(1.0 - tail, k + 1, n - k))
    return low, high


# --- the rates resampled from the runs on disk (no runs) -----------------------------------------

RESAMPLED = {  # estimate -> (the candidate's pool, the baseline, flips, what it measures)
    "false_alarm": (
        "null",
        "stored",
        False,
        "false alarms: 4 of the fresh null members against the stored baseline",
    ),
    "false_alarm_pooled": (
        "null",
        "pooled",
        False,
        "false alarms: 20 + 4 distinct of the baseline and fresh null "
        "members (any baseline, not only the stored one)",
    ),
    "power_shift": (
        "shift",
        "stored",
        False,
        "power vs +2 %: 4 of the shift members against the stored baseline",
    ),
    "power_flips": (
        "null",
        "stored",
        True,
        f"power vs {N_FLIPS} flips: 4 of the fresh null members, "
        f"{N_FLIPS} unanimous verdicts flipped, against the stored baseline",
    ),
}


def runs_of(ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
    """A file's runs: grid verdicts (case, K) and search thresholds (system, K)."""
    from stonedem.study.equivalence import _stack

    return _stack(ds, "collapsed", "case"), _stack(ds, "threshold", "system")


def pooled_runs(
    baseline: xr.Dataset, candidates: list[xr.Dataset]
) -> tuple[np.ndarray, np.ndarray]:
    """Every candidate's runs side by side, in the baseline's case and system order."""
    from stonedem.study.equivalence import matched

    pairs = [runs_of(matched(baseline, c)) for c in candidates]
    if not pairs:
        return np.zeros((baseline.sizes["case"], 0)), np.zeros((baseline.sizes.get("system", 0), 0))
    return np.concatenate([v for v, _ in pairs], axis=1), np.concatenate(
        [t for _, t in pairs], axis=1
    )


def resampled_rates(
    baseline: xr.Dataset,
    nulls: list[xr.Dataset],
    shifts: list[xr.Dataset],
    resamples: int,
    n_permutations: int,
    seed: int,
) -> xr.Dataset:
    """Each :data:`RESAMPLED` estimate's rejection rate over ``resamples`` random picks of runs
    already made (no new run): the draws' rates bound a 2 % false-alarm rate only loosely (0 of
    10 draws: <= 31 % at 95 %); members picked again and again are the same runs, so these are
    estimates of the test's rates on this pool, not independent trials. Empty without pools."""
    from stonedem.study.permutation import permutation_test

    base_v, base_t = runs_of(baseline)
    pools = {"null": pooled_runs(baseline, nulls), "shift": pooled_runs(baseline, shifts)}
    tolerance = (
        np.asarray(baseline.search_tolerance.values, dtype=float)
        if "system" in baseline.dims
        else np.zeros(0)
    )
    unanimous = np.flatnonzero(base_v.min(axis=1) == base_v.max(axis=1))
    rng = np.random.default_rng(seed)
    names = [n for n, (pool, *_) in RESAMPLED.items() if pools[pool][0].shape[1] >= MEMBERS]
    p_v = np.full((len(names), resamples), np.nan)
    p_t = np.full((len(names), resamples), np.nan)
    rejected = np.zeros((len(names), resamples), dtype=bool)
    for e, name in enumerate(names):
        pool, against, flips, _ = RESAMPLED[name]
        pool_v, pool_t = pools[pool]
        if against == "pooled":
            pool_v, pool_t = (
                np.concatenate([base_v, pool_v], axis=1),
                np.concatenate([base_t, pool_t], axis=1),
            )
        for r in range(resamples):
            if against == "pooled":
                picked = rng.choice(pool_v.shape[1], base_v.shape[1] + MEMBERS, replace=False)
                b_v, b_t = pool_v[:, picked[MEMBERS:]], pool_t[:, picked[MEMBERS:]]
                picked = picked[:MEMBERS]
            else:
                b_v, b_t = base_v, base_t
                picked = rng.choice(pool_v.shape[1], MEMBERS, replace=False)
            c_v, c_t = pool_v[:, picked].copy(), pool_t[:, picked]
            if flips:
                chosen = rng.choice(unanimous, N_FLIPS, replace=False)
                c_v[chosen, :] = 1.0 - base_v[chosen, :1]
            result = permutation_test(
                b_v,
                b_t,
                c_v,
                c_t,
                tolerance,
                n_permutations=n_permutations,
                seed=int(rng.integers(2**32)),
            )
            p_v[e, r], p_t[e, r], rejected[e, r] = result["p_v"], result["p_t"], result["reject"]
    pool_sizes = [
        pools[RESAMPLED[n][0]][0].shape[1] + (base_v.shape[1] if RESAMPLED[n][1] == "pooled" else 0)
        for n in names
    ]
    return xr.Dataset(
        {
            "resampled_rate": (
                "estimate",
                rejected.mean(axis=1) if resamples else np.full(len(names), np.nan),
                {"units": "1", "long_name": "fraction of the resamples the test rejects"},
            ),
            "resampled_pool": (
                "estimate",
                np.array(pool_sizes, dtype=np.int32),
                {"units": "1", "long_name": "runs the resamples are picked from"},
            ),
            "resampled_p_v": (
                ("estimate", "resample"),
                p_v,
                {"units": "1", "long_name": "permutation p of S_v"},
            ),
            "resampled_p_t": (
                ("estimate", "resample"),
                p_t,
                {"units": "1", "long_name": "permutation p of S_T"},
            ),
            "resampled_what": (
                "estimate",
                np.array([RESAMPLED[n][3] for n in names], dtype=object),
                {"long_name": "what the estimate measures, and how its resamples are picked"},
            ),
        },
        coords={
            "estimate": (
                "estimate",
                np.array(names, dtype=object),
                {"long_name": "resampled estimate"},
            ),
            "resample": (
                "resample",
                np.arange(resamples, dtype=np.int32),
                {"long_name": "resample index"},
            ),
        },
    )


ROW_VARIABLES = {  # name -> (units (None: text), long name)
    "draw_kind": (None, "null, shift, flips, friction, edge_normal or tilt"),
    "draw_index": ("1", "d, the draw's index within its kind"),
    "first_member": ("1", "the candidate's first member j (members j .. j + members - 1)"),
    "members": ("1", "K_N, the candidate's members"),
    "verdict_a": (None, "layer A: pass, fail, not run or not requested"),
    "verdict_b": (None, "layer B: pass, fail, not run or not requested"),
    "verdict_c": (None, "layer C: pass, fail, not run or not requested"),
    "rejected": ("1", "1: judged not equivalent"),
    "p_v": ("1", "permutation p of S_v (collapse fractions)"),
    "p_t": ("1", "permutation p of S_T (median thresholds)"),
    "s_v": ("1", "S_v: chi2-like distance of the grid's collapse fractions"),
    "s_t": ("1", "S_T: median ln threshold shifts, in search brackets"),
    "unanimous_flips": ("1", "candidate flips of cases every baseline member agrees on"),
    "flipped_cases": (None, "flips draws: the cases whose verdicts were flipped"),
    "candidate_source": (None, "code version the candidate ran (stonedem.io.netcdf.code_version)"),
    "candidate_seconds": (
        "s",
        "wall time of making the candidate's runs and checks (flips: 0, no runs)",
    ),
}


def calibration_dataset(rows: list[dict], attrs: dict) -> xr.Dataset:
    names = np.array([f"{r['draw_kind']}/{r['draw_index']}" for r in rows], dtype=object)
    data = {}
    for name, (units, long_name) in ROW_VARIABLES.items():
        values = [r.get(name) for r in rows]
        if units is None:
            data[name] = (
                "draw",
                np.array(["" if v is None else str(v) for v in values], dtype=object),
                {"long_name": long_name},
            )
        else:
            kind = (
                np.int32
                if name in ("draw_index", "first_member", "members", "rejected", "unanimous_flips")
                else float
            )
            data[name] = (
                "draw",
                np.array([np.nan if v is None else v for v in values], dtype=kind),
                {"units": units, "long_name": long_name},
            )
    return xr.Dataset(
        data, coords={"draw": ("draw", names, {"long_name": "kind/d of a draw"})}, attrs=attrs
    )


def summary_attrs(rows: list[dict]) -> dict:
    """The rates (with Clopper-Pearson 95 % intervals) and the report-only draws' numbers."""
    attrs = {}
    for kind, name in (
        ("null", "false_alarm_rate"),
        ("shift", "power_shift"),
        ("flips", "power_flips"),
    ):
        picked = [r for r in rows if r["draw_kind"] == kind]
        k, n = sum(r["rejected"] for r in picked), len(picked)
        low, high = binomial_interval(k, n)
        attrs.update(
            {
                name: k / n if n else math.nan,
                f"{name}_low": low,
                f"{name}_high": high,
                f"{name}_draws": n,
                f"{name}_rejections": k,
                f"{name}_target": TARGETS[name],
            }
        )
    for kind in SINGLE:
        picked = [r for r in rows if r["draw_kind"] == kind]
        if picked:
            attrs.update(
                {
                    f"{kind}_p_v": picked[0]["p_v"],
                    f"{kind}_p_t": picked[0]["p_t"],
                    f"{kind}_rejected": picked[0]["rejected"],
                    f"{kind}_verdicts": " ".join(picked[0][f"verdict_{x}"] for x in "abc"),
                }
            )
        else:  # not drawn yet (the draws are made over several runs): said so, not left out
            attrs.update(
                {
                    f"{kind}_p_v": math.nan,
                    f"{kind}_p_t": math.nan,
                    f"{kind}_rejected": "not run yet",
                    f"{kind}_verdicts": "not run yet",
                }
            )
    return attrs


def summary_lines(ds: xr.Dataset) -> list[str]:
    lines = []
    for r in range(ds.sizes["draw"]):
        row = ds.isel(draw=r)
        lines.append(
            f"  {str(row.draw.values):<14} j "
            f"{int(row.first_member)}..{int(row.first_member) + int(row.members) - 1}"
            f"  A {row.verdict_a.values} B {row.verdict_b.values} C {row.verdict_c.values}"
            f"  p_v {float(row.p_v):.3g} p_t {float(row.p_t):.3g}  "
            f"{'REJECTED' if int(row.rejected) else 'equivalent'}"
        )
    a = ds.attrs
    for name, what in (
        ("false_alarm_rate", "false alarms"),
        ("power_shift", "power vs +2 %"),
        ("power_flips", f"power vs {N_FLIPS} flips"),
    ):
        if a[f"{name}_draws"]:
            lines.append(
                f"{what}: {a[f'{name}_rejections']}/{a[f'{name}_draws']} = {a[name]:.2f} "
                f"(95 % {a[f'{name}_low']:.2f}..{a[f'{name}_high']:.2f}; target "
                f"{'<=' if name == 'false_alarm_rate' else '>='} {a[f'{name}_target']:g})"
            )
    if "estimate" in ds.dims:
        for name in ds.estimate.values:
            row = ds.sel(estimate=name)
            lines.append(
                f"resampled {name}: {float(row.resampled_rate):.3f} of {ds.sizes['resample']} "
                "picks "
                f"from {int(row.resampled_pool)} runs"
            )
    for kind in SINGLE:
        if f"{kind}_p_v" in a and a[f"{kind}_verdicts"] != "not run yet":
            lines.append(
                f"{kind}: p_v {a[f'{kind}_p_v']:.3g}, p_t {a[f'{kind}_p_t']:.3g}, layers A B C "
                f"{a[f'{kind}_verdicts']}: {'rejected' if a[f'{kind}_rejected'] else 'equivalent'}"
            )
    return lines


# --- the command -------------------------------------------------------------------------------


def build_parser():
    import argparse

    parser = options.parser("python -m benchmarks.equivalence_calibration", __doc__)
    parser.add_argument(
        "--baseline", type=options.path_arg, required=True, help="the baseline ensemble file"
    )
    parser.add_argument(
        "--config",
        type=options.path_arg,
        default=None,
        help="the baseline's config (default: the last file its attrs `config` name)",
    )
    parser.add_argument(
        "--draws", type=int, default=10, help="D, draws of null, shift and flips (default 10)"
    )
    parser.add_argument(
        "--only",
        nargs="+",
        default=list(KINDS),
        help=f"kinds to draw, of {' '.join(KINDS)} "
        "(default all; the summary covers every draw found in --work)",
    )
    parser.add_argument(
        "--jobs", type=int, default=os.cpu_count() or 1, help="worker processes (default: the CPUs)"
    )
    parser.add_argument(
        "--permutations",
        type=int,
        default=10_000,
        help="layer C's random assignments (default 10000)",
    )
    parser.add_argument(
        "--seed", type=int, default=0, help="seed of the flips and permutations (default 0)"
    )
    parser.add_argument(
        "--resamples",
        type=int,
        default=RESAMPLES,
        help=f"random picks of the runs on disk per resampled rate (default {RESAMPLES}; 0: none)",
    )
    parser.add_argument(
        "--work", type=options.path_arg, default=WORK, help=f"the draws' files (default {WORK})"
    )
    parser.add_argument(
        "--out", type=options.path_arg, default=None, help="calibration.nc (default: in --work)"
    )
    parser.add_argument(
        "--make-draw", default=None, help=argparse.SUPPRESS
    )  # the edge_normal child
    return parser


def check_args(args) -> dict:
    from stonedem.study.equivalence import read_ensemble
    from stonedem.study.grid import config_cases

    baseline = read_ensemble(args.baseline, "--baseline")
    draws = options.number(args.draws, "--draws", lo=1, hi=100, whole=True, example="10")
    jobs = options.number(args.jobs, "--jobs", lo=1, hi=256, whole=True, example="2")
    n_permutations = options.number(
        args.permutations, "--permutations", lo=200, hi=1_000_000, whole=True, example="10000"
    )
    seed = options.number(args.seed, "--seed", lo=0, hi=2**32 - 1, whole=True, example="0")
    resamples = options.number(
        args.resamples, "--resamples", lo=0, hi=100_000, whole=True, example=str(RESAMPLES)
    )
    only = options.chosen(args.only, "--only", KINDS)
    config = args.config
    if config is None:
        named = str(baseline.attrs.get("config", "")).split()
        if not named:
            raise InputError(
                "--config", "the baseline names no config (attrs `config`)", "give --config"
            )
        config = Path(named[-1])
    config_dict, _ = options.study_config(config, Path("records"))
    names = [
        str(v) for dim in ("case", "system") if dim in baseline.dims for v in baseline[dim].values
    ]
    studies = list(dict.fromkeys(name.split("/")[0] for name in names))
    if any(s not in (config_dict.get("studies") or {}) for s in studies):
        raise InputError(
            "--config",
            f"lacks a study of the baseline ({', '.join(studies)})",
            "give the baseline's config",
        )
    cases, systems = [], []
    for group in config_cases(config_dict, studies).values():
        for case in group:
            (systems if case.search is not None else cases).append(case)
    mine = [f"{c.study}/{c.id}" for c in cases + systems]
    if sorted(mine) != sorted(names):
        raise InputError(
            "--config",
            f"its cases differ from the baseline's ({len(mine)} against {len(names)})",
            "give the config the baseline was made with (its attrs `config`)",
        )
    if "system" in baseline.dims and "shift" in only:
        pga = {str(p) for p in baseline.search_parameter.values} - {"pga", "pga_scale", "amplitude"}
        if pga:
            raise InputError(
                "--only shift",
                f"searches over {', '.join(sorted(pga))}: not moved by the base motion",
                "leave shift out",
            )
    work = Path(args.work)
    out = options.output_file(
        args.out or work / "calibration.nc", "--out", suffixes=(".nc",), inputs=[args.baseline]
    )
    if work.exists() and not work.is_dir():
        raise InputError("--work", f"{work} is not a folder", "give a folder for the draws' files")
    members = [int(j) for j in baseline.member.values]
    return {
        "baseline": baseline,
        "baseline_path": Path(args.baseline).resolve(),
        "config": Path(config).resolve(),
        "cases": cases,
        "systems": systems,
        "draws": draws,
        "jobs": jobs,
        "n_permutations": n_permutations,
        "seed": seed,
        "resamples": resamples,
        "only": only,
        "work": work.resolve(),
        "out": out.resolve(),
        "first_fresh": max(members) + 1,
    }


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)

    def command():
        from stonedem.io.netcdf import code_version, write_dataset
        from stonedem.study.ensemble import machine
        from stonedem.study.equivalence import read_ensemble

        plan = check_args(args)
        baseline, work = plan["baseline"], plan["work"]
        work.mkdir(parents=True, exist_ok=True)
        if args.make_draw == "edge_normal":  # the child on the patched worktree's code
            members = draw_members(plan["first_fresh"], 0)
            make_candidate(plan, "edge_normal", 0, members, candidate_path(work, "edge_normal", 0))
            return 0
        rows, made_draws = [], {"null": [], "shift": []}
        for kind in KINDS:
            count = 1 if kind in SINGLE else plan["draws"]
            for d in range(count):
                members = draw_members(plan["first_fresh"], d)
                made = kind if kind != "flips" else "null"  # a flips draw is its null draw's data
                path = candidate_path(work, made, d)
                seconds = math.nan
                if not usable_draw(path, made, d, members, baseline):
                    if kind not in plan["only"]:
                        continue
                    print(
                        f"{kind} draw {d}: members {members[0]}..{members[-1]} ...",
                        file=sys.stderr,
                        flush=True,
                    )
                    if kind == "edge_normal":
                        seconds = run_edge_normal(plan, members, path)
                    else:
                        seconds = make_candidate(plan, made, d, members, path)
                candidate = read_ensemble(path, f"draw {kind} {d}")
                if kind in made_draws:
                    made_draws[kind].append(candidate)
                flips, layers = [], ["C"]
                if kind == "flips":
                    candidate, flips = flipped(candidate, baseline, plan["seed"] + d)
                elif kind in ("null", "edge_normal"):
                    layers = [
                        x
                        for x in "ABC"
                        if x == "C" or {"A": "check", "B": "scene"}[x] in baseline.dims
                    ]
                row = judged(baseline, candidate, layers, plan["seed"] + d, plan["n_permutations"])
                row.update(
                    draw_kind=kind,
                    draw_index=d,
                    first_member=members[0],
                    members=len(members),
                    flipped_cases=" ".join(flips),
                    candidate_source=str(candidate.attrs.get("source", "")),
                    candidate_seconds=0.0
                    if kind == "flips"
                    else float(candidate.attrs.get("wall_seconds", seconds)),
                )
                rows.append(row)
        if not rows:
            raise InputError("--only", "no draw made or found in --work", "give kinds to draw")
        from stonedem.study.runner import library_versions

        attrs = {
            "title": "equivalence test calibration: false-alarm rate and power (issue 44, item 6)",
            **summary_attrs(rows),
            "baseline": str(plan["baseline_path"]),
            "baseline_source": str(baseline.attrs.get("source", "")),
            "baseline_machine": str(baseline.attrs.get("machine", "")),
            "baseline_members": int(baseline.sizes["member"]),
            "config": str(plan["config"]),
            "candidate_members": MEMBERS,
            "shift_factor": SHIFT,
            "friction_factor": FRICTION,
            "flips_per_draw": N_FLIPS,
            "alpha": 0.005,
            "permutations": plan["n_permutations"],
            "seed": plan["seed"],
            "confidence": CONFIDENCE,
            "interval": "Clopper-Pearson",
            "edge_normal_patch": PATCH.name,
            "source": code_version(),
            "machine": machine(),
            **library_versions(),
            "command": " ".join(
                ["benchmarks/equivalence_calibration.py", *(sys.argv[1:] if argv is None else argv)]
            ),
        }
        ds = calibration_dataset(rows, attrs)
        if plan["resamples"]:
            print(
                f"resampling the runs on disk ({plan['resamples']} picks per rate) ...",
                file=sys.stderr,
                flush=True,
            )
            resampled = resampled_rates(
                baseline,
                made_draws["null"],
                made_draws["shift"],
                plan["resamples"],
                RESAMPLE_PERMUTATIONS,
                plan["seed"],
            )
            ds = xr.merge([ds, resampled], combine_attrs="override")
            ds.attrs.update(
                {
                    f"resampled_{n}": float(r)
                    for n, r in zip(resampled.estimate.values, resampled.resampled_rate.values)
                }
            )
            ds.attrs.update(
                resamples=plan["resamples"], resample_permutations=RESAMPLE_PERMUTATIONS
            )
        write_dataset(ds, plan["out"])
        for line in summary_lines(ds):
            print(line)
        print(f"wrote {plan['out']}")
        return 0

    return options.run(command)


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    sys.exit(main())
