"""Wall benchmark: how the unstated details move Tables 1 and 3 (issue 15).

For each edge-supported table case (Orduña 1-2, Chee Liang 2-3 ... 10-11) the pushover runs
with the case file as given and with one detail changed at a time:

- the edge restraints: pins at the edge blocks' centres (``at: centre``, the first wave), a
  continuous line at the panel edge (``hold: line``), a row of pins on that line
  (``hold: points``);
- the interface law: the Fig. 10 torsion reduction on no-tension joints only (not on mortar
  joints, ``joints.torsion_under_bending: no_tension``), and both bending stiffnesses released
  when one component yields (Eq. 13 read literally, ``joints.bending_release: both``);
- the interface areas (mortared walls): those of the bare bricks instead of the cells
  (brick plus half the joint all round), the same panel;
- where the case has them: the base support joint mortared (the wall's tension and cohesion)
  instead of a no-tension bearing; the top line holding translations (arching), not only
  the out-of-plane one; the side lines 15, 30.5 (a half block's centre), 45 and 61 mm (a
  full block's centre) inside the panel edges;
- which joints carry each mechanism (mortared walls): the tensile strength or the cohesion of
  the bed or of the head joints alone x 1.5;
- Table 2 walls held by fixed lateral columns (S11 ... S5): the fixed column one block deep,
  toothed as a bonded orthogonal wall's courses are (every block whose centre lies within b
  of the edge), instead of the edge block of each course.

Prints λ (or p in kPa) and the error against the manuscript's DEM column per variant and
writes ``results/walls/supports.csv``.

    python -m benchmarks.wall_supports [--only chee_liang_2_3 s5 ...] [--out results/walls]
"""

from __future__ import annotations

import copy
import dataclasses
import os
import sys
import time
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks import options
from stonedem.wall.case import case_from_dict, read_case
from stonedem.wall.pushover import ConvergenceError, pushover

ROOT = Path(__file__).resolve().parents[1]
CASES = [
    "orduna_case1",
    "orduna_case2",
    "chee_liang_2_3",
    "chee_liang_8_12",
    "chee_liang_14_15",
    "chee_liang_4_5",
    "chee_liang_9_13",
    "chee_liang_10_11",
]
COLUMN_CASES = [
    "s11",
    "s12",
    "s13",
    "s15",
    "s6",
    "s1_s2_s3",
    "s5",
]  # Table 2, fixed lateral columns


def _edge_restraints(spec, change):
    for r in spec["restraints"]:
        if r.get("support", "joint" if r["edge"] == "base" else "block") == "block":
            change(r)


def at_centre(spec):
    def change(r):
        r.pop("hold", None), r.pop("offset", None)
        r["at"] = "centre"

    _edge_restraints(spec, change)


def hold(kind):
    def variant(spec):
        def change(r):
            r["at"], r["hold"] = "edge", kind

        _edge_restraints(spec, change)

    return variant


def bare_brick_interfaces(model):
    """The same panel, interfaces of the bare bricks instead of the cells: a head joint a high
    (not a + e), a bed overlap (b - e)/2 wide (not (b + e)/2); caps, areas and stiffness follow."""
    from stonedem.wall.panel import KIND_BED, KIND_HEAD

    panel = copy.copy(model.panel)
    e = float(panel.block["joint_thickness"])
    panel.width = panel.width.copy()
    panel.width[panel.kind == KIND_HEAD] -= e
    panel.width[panel.kind == KIND_BED] -= e
    return dataclasses.replace(model, panel=panel)  # rebuilt: compatibility, sections, reduction


def columns_one_block_deep(model):
    """Fixed lateral columns one block deep: every block whose centre lies within b of a fixed
    edge (in running bond: the full edge block of one course, the half block and the full
    block beside it in the next, toothed like a bonded orthogonal wall), not only the edge
    block of each course (manuscript 3.2 says only "restraining block translations and
    rotations along one or both lateral columns")."""

    panel = model.panel
    fixed = model.fixed.reshape(-1, 6).copy()
    x = panel.centre[:, 0]
    length = float(np.max(panel.centre[:, 0] + panel.size[:, 0] / 2))
    depth = float(panel.block["b"]) + float(panel.block.get("joint_thickness", 0.0)) + 1e-9
    column = fixed.all(axis=1)
    if (column & (x < length / 2)).any():
        fixed[x <= depth] = True
    if (column & (x > length / 2)).any():
        fixed[x >= length - depth] = True
    return dataclasses.replace(
        model, fixed=fixed.ravel()
    )  # rebuilt: the reduction of the restraints


def base_bonded(spec):
    """The base support joint with the wall's own mortar (tension, cohesion) instead of a
    no-tension, cohesionless bearing: the wall mortared to its base."""
    for r in spec["restraints"]:
        if r["edge"] == "base" and r.get("support", "joint") == "joint":
            r.pop("joint", None)


def top_held_in_plane(spec):
    """The top line holds translations (vertical and along the edge too), not only out of
    plane: a top beam that stops the wall from lifting as it bends (arching)."""
    for r in spec["restraints"]:
        if r["edge"] == "top":
            r["fix"] = "translations"


def side_lines_inside(distance):
    """The left and right lines ``distance`` metres inside the panel edges (at: offset): the
    span between the supports is not given, only the specimen's length."""

    def variant(spec):
        for r in spec["restraints"]:
            if r["edge"] in ("left", "right") and r.get("at") == "edge":
                r["at"], r["offset"] = "offset", distance

    return variant


def has_side_lines(spec):
    return any(r["edge"] in ("left", "right") and r.get("at") == "edge" for r in spec["restraints"])


def has_base_joint_override(spec):
    return any(r["edge"] == "base" and "joint" in r for r in spec["restraints"])


def has_top_line(spec):
    return any(r["edge"] == "top" for r in spec["restraints"])


VARIANTS = {
    "as given": None,
    "pins at centres": at_centre,
    "line (hold: line)": hold("line"),
    "pins on the line (hold: points)": hold("points"),
}
# variants that apply only where the case has the detail they change
CONDITIONAL_VARIANTS = {
    "base mortared (bonded support joint)": (base_bonded, has_base_joint_override),
    "top line holds translations (arching)": (top_held_in_plane, has_top_line),
    **{
        f"side lines {1000 * d:g} mm inside": (side_lines_inside(d), has_side_lines)
        for d in (0.015, 0.0305, 0.045, 0.061)
    },
}
LAW_VARIANTS = {
    "Fig. 10 on no-tension joints only": {"torsion_all_joints": False},
    "both bending stiffnesses released (Eq. 13)": {"release_both_rotations": True},
}


# which joints carry a mechanism: one strength of one kind of interface x 1.5 (mortared walls)
JOINT_LEVERS = {
    f"{kind} joints' {label} x 1.5": (kind, field, 1.5)
    for kind in ("bed", "head")
    for label, field in (("tensile strength", "tensile_strength"), ("cohesion", "cohesion"))
}


def scale_joint_strength(model, kind, field, factor):
    from stonedem.wall.panel import KIND_BED, KIND_HEAD

    values = getattr(model.strength, field).copy()
    values[model.panel.kind == {"bed": KIND_BED, "head": KIND_HEAD}[kind]] *= factor
    return dataclasses.replace(model.strength, **{field: values})


def run(spec, name, law=None, transform=None, lever=None):
    case = case_from_dict(spec, name)
    if transform:
        case.model = transform(case.model)
    if law:
        case.model.strength = dataclasses.replace(case.model.strength, **law)
    if lever:
        case.model.strength = scale_joint_strength(case.model, *lever)
    t0 = time.perf_counter()
    try:
        r = pushover(case.model, case.settings, case.control_block)
    except ConvergenceError as err:
        return float("nan"), f"failed: {err}", time.perf_counter() - t0
    return r.lambda_max, r.status, time.perf_counter() - t0


def build_parser():
    ap = options.parser("python -m benchmarks.wall_supports", __doc__)
    ap.add_argument(
        "--only",
        nargs="*",
        help="case file stems, each once, from: "
        + " ".join(CASES + COLUMN_CASES)
        + " (default: all of them, Tables 1 and 3 and the Table 2 walls held by lateral columns)",
    )
    ap.add_argument(
        "--out",
        type=options.path_arg,
        default=str(ROOT / "results" / "walls"),
        help="output folder (writes supports.csv)",
    )
    return ap


def check_args(args):
    """(case names, output folder), or an InputError before anything runs."""
    names = (
        options.chosen(args.only, "--only", CASES + COLUMN_CASES, empty_ok=True)
        or CASES + COLUMN_CASES
    )
    for name in names:
        options.input_file(
            ROOT / "config" / "walls" / f"{name}.yaml",
            "--only",
            "case file config/walls/<name>.yaml",
        )
    return names, options.output_folder(args.out, "--out", files=("supports.csv",))


def main(argv=None) -> int:
    """Options and output folder checked first (one line, exit 2); then the variants."""
    args = build_parser().parse_args(argv)
    return options.run(lambda: supports(*check_args(args)))


def supports(names, out: Path) -> int:
    try:
        os.nice(19)
    except OSError:
        pass
    rows = []
    print(f"{'case':>18} {'variant':>44} {'ours':>9} {'DEM':>8} {'error':>7} {'s':>5}", flush=True)
    for name in names:
        base = read_case(ROOT / "config" / "walls" / f"{name}.yaml")
        base.pop("name", None)
        ref = base.get("reference", {})
        dem = ref.get("p_dem", ref.get("lambda_dem"))
        scale = 1e-3 if "p_dem" in ref else 1.0
        if name in COLUMN_CASES:
            runs = [
                ("as given", None, None, None, None),
                ("lateral columns one block deep", None, None, columns_one_block_deep, None),
            ]
        else:
            runs = [(label, change, None, None, None) for label, change in VARIANTS.items()]
            runs += [
                (label, change, None, None, None)
                for label, (change, applies) in CONDITIONAL_VARIANTS.items()
                if applies(base)
            ]
            runs += [(label, None, law, None, None) for label, law in LAW_VARIANTS.items()]
        if base["panel"].get("joint_thickness"):
            runs.append(("interfaces of the bare bricks", None, None, bare_brick_interfaces, None))
        if base["joints"].get("kind") == "mortar":
            runs += [(label, None, None, None, lever) for label, lever in JOINT_LEVERS.items()]
        for label, change, law, transform, lever in runs:
            spec = copy.deepcopy(base)
            if change:
                change(spec)
            lam, status, seconds = run(spec, name, law, transform, lever)
            err = lam / dem - 1.0
            rows.append(
                {
                    "case": name,
                    "variant": label,
                    "ours": round(lam * scale, 4),
                    "manuscript_dem": dem * scale,
                    "error": round(err, 4),
                    "unit": "kPa" if scale != 1.0 else "lambda",
                    "status": status,
                    "seconds": round(seconds, 1),
                }
            )
            print(
                f"{name:>18} {label:>44} {lam * scale:9.4g} {dem * scale:8.4g} {err:+7.1%} "
                f"{seconds:5.1f}",
                flush=True,
            )
    path = options.write_csv(out / "supports.csv", rows)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())  # one-line errors, exit 2 on bad input, 130 on Ctrl-C
