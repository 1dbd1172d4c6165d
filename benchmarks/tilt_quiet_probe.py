"""Why the tilt draw of the calibration is rejected: the tilt, or the quiet lead? (issue 44, item 1)

A tilted member is not at rest, so the engine integrates its quiet lead from t = 0
(:func:`stonedem.engine.quiet.quiet_steps`); the baseline's k_n members settle and are carried
rigidly by the base until the first loud instant. The tilt draw therefore differs from the
baseline in two ways. This script separates them on Table 7.1 systems: each threshold search
run by member j as the baseline runs it (quiet lead skipped), by the same member with the
quiet lead integrated (``skip_quiet`` off, no tilt), and by the two tilt signs (j even: -1e-6
rad, odd: +1e-6 rad; a tilted scene integrates its quiet lead anyway).

    python -m benchmarks.tilt_quiet_probe [--systems ID ...] [--member 20]
        [--out benchmarks/ensemble/2026-11-28/tilt_quiet_probe.nc]
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np
import xarray as xr

from benchmarks import options
from stonedem.errors import InputError

SYSTEMS = ("rec-kalamata_standin_izmit_izt270_drums-1", "rec-athens_standin_kocaeli_arc000_drums-1")
VARIANTS = {  # name -> (perturbation, member offset, quiet lead integrated, what it is)
    "baseline_path": (
        "stiffness",
        0,
        False,
        "k_n member j, quiet lead skipped (as the baseline runs)",
    ),
    "quiet_lead_integrated": (
        "stiffness",
        0,
        True,
        "k_n member j, quiet lead integrated (skip_quiet off)",
    ),
    "tilt_negative": ("tilt", 0, True, "tilt member j (j even: -1e-6 rad), quiet lead integrated"),
    "tilt_positive": ("tilt", 1, True, "tilt member j + 1 (odd: +1e-6 rad), quiet lead integrated"),
}
CONFIG = Path("config/config.yaml")
RECORDS = Path("records")
STUDY = "standalone_records"


def probe(system, member: int) -> dict:
    """{variant: (threshold, survived, runs)} of one search system."""
    from stonedem.study import ensemble

    plain = ensemble.member_scene
    out = {}
    try:
        for name, (perturbation, offset, integrated, _) in VARIANTS.items():

            def member_scene(scene, j, kind="stiffness", integrated=integrated):
                built = plain(scene, j, kind)
                return dataclasses.replace(built, skip_quiet=False) if integrated else built

            ensemble.member_scene = member_scene
            result = ensemble.member_search(system, member + offset, perturbation)
            out[name] = (result["upper"], result["lower"], result["n_runs"])
            print(
                f"{system.id} {name}: threshold {result['upper']:.4g} m/s2 (survived "
                f"{result['lower']:.4g}, "
                f"{result['n_runs']} runs)",
                file=sys.stderr,
                flush=True,
            )
    finally:
        ensemble.member_scene = plain
    return out


def main(argv=None) -> int:
    parser = options.parser("python -m benchmarks.tilt_quiet_probe", __doc__)
    parser.add_argument(
        "--systems",
        nargs="+",
        default=list(SYSTEMS),
        help=f"{STUDY} systems (default: {' '.join(SYSTEMS)})",
    )
    parser.add_argument(
        "--member",
        type=int,
        default=20,
        help="member j of the k_n and tilt-negative runs (even; default 20)",
    )
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=Path("results/bench/tilt_quiet_probe.nc"),
        help="the dataset (default results/bench/tilt_quiet_probe.nc)",
    )
    args = parser.parse_args(argv)

    def command():
        from stonedem.io.netcdf import code_version, write_dataset
        from stonedem.study.runner import machine

        member = options.number(args.member, "--member", lo=0, hi=998, whole=True, example="20")
        if member % 2:
            raise InputError(
                "--member", f"{member} is odd: its tilt is +1e-6 rad", "give an even j, e.g. 20"
            )
        out = options.output_file(args.out, "--out", suffixes=(".nc",))
        config, known = options.study_config(CONFIG, RECORDS)
        _, searched = options.chosen_cases(config, known, [STUDY], RECORDS)
        systems = {system.id: system for system in searched}
        chosen = options.chosen(args.systems, "--systems", list(systems))
        rows = {name: probe(systems[name], member) for name in chosen}
        names = list(VARIANTS)
        data = {}
        for k, (var, units, long_name) in enumerate(
            (
                ("threshold", "m s-2", "collapse threshold (smallest PGA that collapsed)"),
                ("survived", "m s-2", "largest PGA below it that survived"),
                ("n_runs", "1", "runs of the search"),
            )
        ):
            data[var] = (
                ("system", "variant"),
                np.array([[rows[s][v][k] for v in names] for s in chosen], dtype=float),
                {"units": units, "long_name": long_name},
            )
        ds = xr.Dataset(
            data,
            coords={
                "system": (
                    "system",
                    np.array(chosen, dtype=object),
                    {"long_name": f"{STUDY} search system"},
                ),
                "variant": (
                    "variant",
                    np.array(names, dtype=object),
                    {"long_name": "how the member is run"},
                ),
                "variant_description": (
                    "variant",
                    np.array([VARIANTS[v][3] for v in names], dtype=object),
                    {"long_name": "what the variant is"},
                ),
            },
            attrs={
                "title": "tilt or quiet lead: the calibration's tilt draw taken apart (issue 44)",
                "member": member,
                "tilt_rad": 1e-6,
                "config": str(CONFIG),
                "study": STUDY,
                "source": code_version(),
                "machine": machine(),
                "command": " ".join(
                    ["benchmarks/tilt_quiet_probe.py", *(sys.argv[1:] if argv is None else argv)]
                ),
            },
        )
        write_dataset(ds, out)
        print(f"wrote {out}")
        return 0

    return options.run(command)


if __name__ == "__main__":
    sys.exit(main())
