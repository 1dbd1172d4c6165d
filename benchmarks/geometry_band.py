"""Does the equivalence test need the geometry's last bits in its baseline? The judgements behind
docs/method/equivalence.md, "The geometry's last bits" (issue 45, 2026-11-29).

Each draw is a candidate ensemble (:mod:`stonedem.study.ensemble`, fresh members j >= 20) judged
by :func:`stonedem.study.equivalence.judge` against one of the two stored K = 20 baselines:
``stiffness`` (benchmarks/ensemble/2026-11-28: k_n x (1 - j 2^-52)) or ``geometry``
(benchmarks/ensemble/2026-11-29: that and every coordinate x (1 + j 2^-52)). A draw of several
candidate files pools their members (8 = two draws of 4, the size the acceptance rule asks of a
change to the contact law's arithmetic). The candidates live in ``--work``; each was made from
the repository root of the commit named, with ``--config config/config.yaml --jobs 2``:

- ``null_geometry*``: the unchanged code (c2deefe), ``--first j --members 4`` (j = 20, 24),
  ``--perturbation geometry``, ``--checks full`` (j = 20) or ``none`` (24), files
  ``null_geometry.nc`` and ``null_geometry_24.nc``;
- ``widen*``: the code with ``geometry_band_widen.patch`` (every body's x coordinates x
  (1 + 2^-52) in every member: a 1-ulp widening, physically nothing) and the environment
  variable STONEDEM_GEO_DRAW=1, ``--first 20``: ``--members 4 --checks full``, stiffness
  members, on c273fdf (the same kernels; file ``widen_stiffness.nc``), and ``--members 8
  --perturbation geometry --checks none`` on c2deefe (``widen_geometry.nc``);
- ``edge_normals*``: 534605d (issue 32's body-frame edge normals on the current kernels,
  ``equivalence_calibration_edge_normals.patch``), ``--perturbation geometry``, members 20..23
  (``--checks full``, ``edge_normals.nc``) and 24..27 (``--checks none``, ``edge_normals_24.nc``);
- ``shift`` and ``friction``: the calibration's draws (``candidate-shift-00.nc``,
  ``candidate-friction-00.nc`` of benchmarks/equivalence_calibration.py: stiffness members with
  the base motion x 1.02, every friction coefficient x 1.01).

    python -m benchmarks.geometry_band --work DIR [--out
    benchmarks/ensemble/2026-11-29/geometry_band.nc]

Writes one row per draw: members, each layer's verdict, S_v and p_v, S_T and p_T, the answer.
"""

from __future__ import annotations

import sys
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np
import xarray as xr

ROOT = Path(__file__).resolve().parents[1]
BASELINES = {
    "stiffness": ROOT / "benchmarks/ensemble/2026-11-28/ensemble.nc",
    "geometry": ROOT / "benchmarks/ensemble/2026-11-29/ensemble.nc",
}
# draw: (baseline, candidate files in --work, layers, what it is)
DRAWS = {
    "widen_vs_stiffness": (
        "stiffness",
        ["widen_stiffness.nc"],
        None,
        "every x one ulp wider, 4 stiffness members",
    ),
    "null_geometry_vs_stiffness": (
        "stiffness",
        ["null_geometry.nc"],
        None,
        "unchanged code, 4 geometry members",
    ),
    "null_geometry": ("geometry", ["null_geometry.nc"], None, "unchanged code, members 20..23"),
    "null_geometry_24": (
        "geometry",
        ["null_geometry_24.nc"],
        ["C"],
        "unchanged code, members 24..27",
    ),
    "null_geometry_pooled": (
        "geometry",
        ["null_geometry.nc", "null_geometry_24.nc"],
        ["C"],
        "unchanged code, members 20..27",
    ),
    "widen_geometry": (
        "geometry",
        ["widen_geometry.nc"],
        ["C"],
        "every x one ulp wider, members 20..27",
    ),
    "edge_normals": (
        "geometry",
        ["edge_normals.nc"],
        None,
        "body-frame edge normals, members 20..23",
    ),
    "edge_normals_24": (
        "geometry",
        ["edge_normals_24.nc"],
        ["C"],
        "body-frame edge normals, members 24..27",
    ),
    "edge_normals_pooled": (
        "geometry",
        ["edge_normals.nc", "edge_normals_24.nc"],
        ["C"],
        "body-frame edge normals, members 20..27",
    ),
    "shift_vs_geometry": (
        "geometry",
        ["candidate-shift-00.nc"],
        ["C"],
        "base motion x 1.02, 4 stiffness members",
    ),
    "friction_vs_geometry": (
        "geometry",
        ["candidate-friction-00.nc"],
        ["C"],
        "friction x 1.01, 4 stiffness members",
    ),
}


def pooled(paths: list[Path]) -> xr.Dataset:
    """One candidate of several files' members (their per-member variables side by side; the
    rest, layers A and B included, from the first file)."""
    first = xr.load_dataset(paths[0])
    if len(paths) == 1:
        return first
    others = [xr.load_dataset(p) for p in paths[1:]]
    per_member = [v for v in first.data_vars if "member" in first[v].dims]
    joined = xr.concat([first[per_member], *(o[per_member] for o in others)], dim="member")
    rest = first[[v for v in first.data_vars if "member" not in first[v].dims]]
    ds = xr.merge([joined, rest], compat="override", join="outer")
    ds.attrs = dict(
        first.attrs, members=int(ds.sizes["member"]), pooled_from=" ".join(p.name for p in paths)
    )
    return ds


def band_dataset(work: Path) -> xr.Dataset:
    from stonedem.io.netcdf import code_version
    from stonedem.study.equivalence import judge

    rows = []
    baselines = {}  # each baseline read once, not once a draw
    for name, (base, files, layers, what) in DRAWS.items():
        paths = [work / f for f in files]
        missing = [p.name for p in paths if not p.is_file()]
        if missing:
            print(f"{name}: not run ({', '.join(missing)} missing in {work})", file=sys.stderr)
            continue
        candidate = pooled(paths)
        if base not in baselines:
            baselines[base] = xr.load_dataset(BASELINES[base])
        verdict = judge(baselines[base], candidate, layers=layers)
        row = {
            "draw": name,
            "baseline": base,
            "what": what,
            "members": int(candidate.sizes["member"]),
            "first_member": int(candidate.member.values.min()),
            "equivalent": verdict.attrs["equivalent"],
        }
        for layer, text in zip(verdict.layer.values, verdict.verdict.values):
            row[f"verdict_{str(layer).lower()}"] = str(text)
        for key in ("s_v", "p_v", "s_t", "p_t"):
            row[key] = float(verdict[key]) if key in verdict else np.nan
        rows.append(row)
        print(
            f"{name}: {row['equivalent']} (A {row.get('verdict_a')}, B {row.get('verdict_b')}, "
            f"C {row.get('verdict_c')}; p_v {row['p_v']:.4g}, p_T {row['p_t']:.4g})"
        )

    def column(key, dtype, long_name, units=None):
        attrs = {"long_name": long_name, **({"units": units} if units else {})}
        return (
            "draw",
            np.array(
                [r.get(key, "not run") if dtype is object else r.get(key, np.nan) for r in rows],
                dtype=dtype,
            ),
            attrs,
        )

    ds = xr.Dataset(
        {
            "baseline": column(
                "baseline",
                object,
                "the stored K = 20 baseline judged against (its members' perturbation)",
            ),
            "what": column("what", object, "the candidate"),
            "members": column(
                "members", np.int32, "candidate members (pooled files: all of them)", "1"
            ),
            "first_member": column("first_member", np.int32, "the candidate's first member j", "1"),
            "verdict_a": column("verdict_a", object, "layer A: pass, fail or not requested"),
            "verdict_b": column("verdict_b", object, "layer B: pass, fail or not requested"),
            "verdict_c": column("verdict_c", object, "layer C: pass, fail or not requested"),
            "s_v": column("s_v", float, "layer C's S_v (collapse fractions)", "1"),
            "p_v": column("p_v", float, "its permutation p", "1"),
            "s_t": column("s_t", float, "layer C's S_T (median thresholds, in brackets)", "1"),
            "p_t": column("p_t", float, "its permutation p", "1"),
            "equivalent": column(
                "equivalent", object, "the answer: yes when every layer run passes"
            ),
        },
        coords={
            "draw": (
                "draw",
                np.array([r["draw"] for r in rows], dtype=object),
                {"long_name": "draw"},
            )
        },
        attrs={
            "title": "equivalence judgements against a stiffness and a geometry baseline "
            "(issue 45)",
            "alpha": 0.005,
            "source": code_version(),
            "command": "python -m benchmarks.geometry_band " + " ".join(sys.argv[1:]),
        },
    )
    return ds


def main(argv=None) -> int:
    from benchmarks import options

    parser = options.parser("python -m benchmarks.geometry_band", __doc__)
    parser.add_argument(
        "--work", type=options.path_arg, required=True, help="folder of the candidate files"
    )
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=ROOT / "benchmarks/ensemble/2026-11-29/geometry_band.nc",
        help="the judgements (.nc)",
    )
    args = parser.parse_args(argv)

    def command():
        from stonedem.errors import InputError
        from stonedem.io.netcdf import write_dataset

        if not args.work.is_dir():
            raise InputError(
                "--work", f"{args.work} is not a folder", "give the folder of the candidate files"
            )
        out = options.output_file(
            args.out,
            "--out",
            suffixes=(".nc",),
            inputs=[*BASELINES.values(), *sorted(args.work.glob("*.nc"))],
        )
        if not any(
            (args.work / name).is_file() for _, files, _, _ in DRAWS.values() for name in files
        ):
            raise InputError(
                "--work",
                f"none of the candidate files is in {args.work}",
                "give the folder of the candidate files this script's docstring names",
            )
        try:
            ds = band_dataset(args.work)
        except (
            InputError
        ):  # the judge's own one line (a candidate of another config, too few members)
            raise
        except (OSError, ValueError) as error:  # a file that is not NetCDF, or not an ensemble's
            raise InputError(
                "--work",
                f"a candidate file could not be read ({type(error).__name__})",
                "give the files this script's docstring names",
            ) from None
        if not ds.sizes.get("draw"):
            raise InputError(
                "--work",
                f"no draw has all its candidate files in {args.work}",
                "give the folder of the candidate files this script's docstring names",
            )
        write_dataset(ds, out)
        print(f"wrote {out}")

    return options.run(command)


if __name__ == "__main__":
    sys.exit(main())
