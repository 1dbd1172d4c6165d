"""Pictures of a simulated case from its dataset alone: a strip of snapshots and a GIF.

A case dataset (``stonedem run``) holds the centroid histories ``x``, ``y``, ``theta`` of every
body and the full scene as JSON in ``attrs["scene"]``. The body outlines are rebuilt from
that scene with the scene loader itself (:func:`stonedem.engine.scene.scene_from_dict`), so the
pictures show exactly the polygons the engine simulated.

``stonedem snapshots CASE.nc [-o OUT.png] [-n 6] [--times 0 1 2]`` and
``stonedem animate CASE.nc [-o OUT.gif] [--fps 20] [--max-frames 300]``. Outputs are written to
a temporary file beside the target and renamed, so bad input leaves no file behind.

matplotlib is used through its object API on an Agg canvas (no pyplot, no global backend
switch), and xarray and matplotlib are imported only when drawing, so ``stonedem --help`` stays
quick.
"""

from __future__ import annotations

import json
import math
import sys
import textwrap
from pathlib import Path

import numpy as np

from stonedem.io.atomic import write_atomically
from stonedem.errors import InputError

ROLE_COLOURS = {
    "base": "#9a9a9a",  # grey ground slab
    "drum": "#e3d3b0",  # limestone
    "capital": "#e3d3b0",
    "block": "#e3d3b0",
    "epistyle": "#b98c5a",  # a darker stone, so the beam reads apart from the columns
}
EDGE_COLOUR = "#3a3a3a"
STONE = ROLE_COLOURS["drum"]
REQUIRED_VARIABLES = ("x", "y", "theta")
REQUIRED_COORDS = ("time", "body", "body_role")
# the view may reach this share of the initial structure's larger side beyond its box,
# enough for a leaning or fallen column, not for a drum thrown far away
VIEW_MARGIN = 0.5
PANEL_AREA = 7.0  # [in2] one strip panel
FRAME_AREA = 20.0  # [in2] one animation frame
GIF_DPI = 90
DECORATION_HEIGHT = 1.4  # [in] titles and axis labels around a panel


# --- reading a case -----------------------------------------------------------------------

def open_case(path: str | Path):
    """A stonedem case dataset read into memory and checked, or an InputError naming the fix."""
    import xarray as xr

    path = Path(path)
    if not path.is_file():
        raise InputError(str(path), "case file not found",
                         "check the path (a .nc file from stonedem run)")
    try:
        with xr.open_dataset(path) as ds:
            ds = ds.load()
    except (OSError, ValueError):
        raise InputError(str(path), "not a readable NetCDF dataset",
                         "give a case dataset written by stonedem run") from None
    check_case(ds, str(path))
    return ds


def check_case(ds, where: str = "dataset") -> None:
    """Refuse a dataset lacking what the drawings need (histories, body roles, the scene)."""
    for name in REQUIRED_VARIABLES + REQUIRED_COORDS:
        if name not in ds.variables:
            raise InputError(f"{where}: {name}", "missing, so this is not a stonedem case dataset",
                             "give a dataset written by stonedem run")
    if "scene" not in ds.attrs:
        raise InputError(f"{where}: attrs.scene", "missing, so the body outlines cannot be rebuilt",
                         "re-run the case with stonedem run (it stores the scene)")
    if ds.sizes["time"] < 1:
        raise InputError(f"{where}: time", "no samples", "re-run the case")


def _as_case(case):
    """Accept a dataset or the path of one."""
    if isinstance(case, (str, Path)):
        return open_case(case)
    check_case(case)
    return case


def body_polygons(ds) -> list[np.ndarray]:
    """Local vertices (n_i, 2) [m] about each centroid, in the dataset's body order.

    Rebuilt from ``attrs["scene"]`` by the scene loader. The excitation is replaced by
    none first: the outlines do not depend on it, and a record file may not exist here.
    """
    from stonedem.engine.scene import scene_from_dict

    if "scene" not in ds.attrs:
        raise InputError("attrs.scene", "the dataset has no scene attribute",
                         "use a dataset written by stonedem run (it stores the scene as JSON)")
    try:
        spec = json.loads(ds.attrs["scene"])
    except (TypeError, json.JSONDecodeError):
        raise InputError("attrs.scene", "not valid JSON", "re-run the case with stonedem run") from None
    spec["excitation"] = {"kind": "none"}
    scene = scene_from_dict(spec)
    names = [str(b) for b in ds["body"].values]
    if scene.body_names != names:
        raise InputError("body", "the dataset's bodies differ from those of its scene",
                         "re-run the case with stonedem run")
    return [body.vertices - body.centroid for body in scene.bodies]


def posed_polygons(local, x, y, theta) -> list[np.ndarray]:
    """World vertices [m] of every body at one time.

    Each local outline is rotated counter-clockwise by theta [rad] about its centroid and
    moved to the centroid position (x, y) [m]; x, y, theta hold one value per body.
    """
    posed = []
    for verts, xi, yi, ti in zip(local, np.atleast_1d(x), np.atleast_1d(y), np.atleast_1d(theta)):
        c, s = math.cos(ti), math.sin(ti)
        wx = xi + c * verts[:, 0] - s * verts[:, 1]
        wy = yi + s * verts[:, 0] + c * verts[:, 1]
        posed.append(np.column_stack([wx, wy]))
    return posed


def _histories(ds) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """time (T,) [s] and x, y, theta (T, body) as plain arrays in (time, body) order."""
    def plain(name):
        return np.asarray(ds[name].transpose("time", "body").values, dtype=float)

    return np.asarray(ds["time"].values, dtype=float), plain("x"), plain("y"), plain("theta")


def _base_displacement(ds) -> np.ndarray | None:
    if "base_displacement" not in ds:
        return None
    return np.asarray(ds["base_displacement"].values, dtype=float)


def collapse_time(ds) -> float | None:
    """Time of collapse [s], None when the case did not collapse."""
    if "collapsed" not in ds or not int(ds["collapsed"]):
        return None
    t = float(ds["collapse_time"]) if "collapse_time" in ds else math.nan
    return t if math.isfinite(t) else None


# --- what to draw -------------------------------------------------------------------------

def snapshot_samples(ds, times=None, n: int = 6) -> np.ndarray:
    """Sample indices of the strip's panels.

    Default: n times evenly spread from the first sample to the last one, or to the
    collapse when the case collapsed; each time is snapped to its nearest sample.
    """
    time = np.asarray(ds["time"].values, dtype=float)
    if times is None:
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise InputError("-n", f"must be a whole number >= 1, got {n!r}", "give e.g. -n 6")
        end = collapse_time(ds)
        targets = np.linspace(time[0], time[-1] if end is None else end, n)
    else:
        targets = np.atleast_1d(np.asarray(times, dtype=float))
        _check_times(targets, time)
    nearest = np.abs(time[None, :] - targets[:, None]).argmin(axis=1)
    _, first = np.unique(nearest, return_index=True)
    return nearest[np.sort(first)]  # in the order asked, each sample once


def _check_times(targets: np.ndarray, time: np.ndarray) -> None:
    if targets.size == 0:
        raise InputError("--times", "no times given", "give one or more times in s")
    slack = 0.5 * (time[1] - time[0]) if len(time) > 1 else 0.0
    for t in targets:
        if not (time[0] - slack <= t <= time[-1] + slack):
            raise InputError("--times", f"{t:g} s is outside the run",
                             f"give times from {time[0]:g} to {time[-1]:g} s")


def frame_samples(n_time: int, max_frames: int = 300, step: int | None = None) -> np.ndarray:
    """Sample indices of the animation frames, first and last sample included.

    Every step-th sample when a step is given and that makes at most max_frames frames;
    otherwise min(n_time, max_frames) samples spread as evenly as whole indices allow.
    """
    if step is not None:
        frames = np.arange(0, n_time, max(1, int(step)))
        if frames[-1] != n_time - 1:
            frames = np.append(frames, n_time - 1)
        if len(frames) <= max_frames:
            return frames
    spread = np.linspace(0, n_time - 1, min(n_time, max_frames))
    return np.floor(spread + 0.5).astype(int)  # spacing >= 1, so the indices are distinct


def structure_bodies(ds) -> list[int]:
    """Indices of the bodies that are not the base."""
    return [i for i, role in enumerate(ds["body_role"].values) if str(role) != "base"]


def body_colours(ds) -> list[str]:
    """Face colour of each body from its role (base grey, stone, epistyle darker)."""
    return [ROLE_COLOURS.get(str(role), STONE) for role in ds["body_role"].values]


def view_box(local, x, y, theta, structure=None) -> tuple[float, float, float, float]:
    """(x_min, x_max, y_min, y_max) [m] shared by every picture of a case.

    The extent of the whole history, clipped to the initial extent of the structure (the
    bodies indexed by ``structure``, default all) widened on each side by VIEW_MARGIN x its
    larger side: a toppled column stays in view, a drum thrown far off or a wide base does
    not shrink the drawing.
    """
    lo, hi = _history_extent(local, x, y, theta)
    start = posed_polygons(local, x[0], y[0], theta[0])
    shown = list(structure) if structure is not None and len(structure) else range(len(local))
    first = np.concatenate([start[i] for i in shown])
    start_lo, start_hi = first.min(axis=0), first.max(axis=0)
    margin = VIEW_MARGIN * float(np.max(start_hi - start_lo))
    lo = np.maximum(lo, start_lo - margin)
    hi = np.minimum(hi, start_hi + margin)
    pad = 0.04 * float(np.max(hi - lo))  # a little air around the drawing
    return lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad


def _history_extent(local, x, y, theta) -> tuple[np.ndarray, np.ndarray]:
    """Lower-left and upper-right corners [m] of every body over every sample."""
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    for i, verts in enumerate(local):
        c, s = np.cos(theta[:, i:i + 1]), np.sin(theta[:, i:i + 1])
        wx = x[:, i:i + 1] + c * verts[:, 0] - s * verts[:, 1]
        wy = y[:, i:i + 1] + s * verts[:, 0] + c * verts[:, 1]
        lo = np.minimum(lo, [np.nanmin(wx), np.nanmin(wy)])
        hi = np.maximum(hi, [np.nanmax(wx), np.nanmax(wy)])
    return lo, hi


# --- titles -------------------------------------------------------------------------------

def default_title(ds) -> str:
    """'name: structure; excitation[; collapsed at t s]' from the dataset's attributes."""
    from stonedem.motion.excitation import excitation_label  # numba: only when drawing

    scene = json.loads(ds.attrs["scene"])
    parts = [structure_label(scene, [str(r) for r in ds["body_role"].values])]
    parts.append(excitation_label(_json_attr(ds, "excitation") or scene.get("excitation") or {}))
    end = collapse_time(ds)
    if end is not None:
        parts.append(f"collapsed at {end:.2f} s")
    name = scene.get("name")
    return (f"{name}: " if name else "") + "; ".join(parts)


def _json_attr(ds, key):
    try:
        return json.loads(ds.attrs[key])
    except (KeyError, TypeError, json.JSONDecodeError):
        return None


def structure_label(scene: dict, roles: list[str]) -> str:
    """E.g. 'column, 4 drums, 6 x 1 m', 'colonnade, 3 columns x 2 drums, epistyle a' or,
    for a scene of listed bodies, '1 block on the base'."""
    spec = scene.get("structure")
    if not isinstance(spec, dict):
        counts = {role: roles.count(role) for role in dict.fromkeys(roles) if role != "base"}
        text = ", ".join(f"{k} {role}{'s' if k > 1 else ''}" for role, k in counts.items())
        return text + (" on the base" if "base" in roles else "")
    kind = spec.get("kind", "structure")
    words = [kind.replace("_", " ")]
    if "n_columns" in spec:
        words.append(f"{spec['n_columns']} columns x {spec.get('n_drums', 1)} drums")
    elif "n_drums" in spec:
        words.append(f"{spec['n_drums']} drums")
    if "height" in spec or "width" in spec:
        words.append(f"{spec.get('height', 6.0):g} x {spec.get('width', 1.0):g} m")
    if "epistyle_type" in spec:
        words.append(f"epistyle {spec['epistyle_type']}")
    return ", ".join(words)


def panel_label(time: np.ndarray, base: np.ndarray | None, i: int, collapse: float | None) -> str:
    """'t = 1.23 s' (and '(collapse)' at the collapse), then the base displacement [m]."""
    text = f"t = {time[i]:.2f} s"
    if collapse is not None and abs(time[i] - collapse) < 1e-9:
        text += " (collapse)"
    if base is not None:
        text += f"\nbase displacement {round(base[i], 3) + 0.0:+.3f} m"  # + 0.0: no '-0.000'
    return text


# --- drawing ------------------------------------------------------------------------------

def _figure(width: float, height: float, layout: str | None = "constrained", dpi: float = 100):
    """A matplotlib Figure on an Agg canvas (no pyplot, so no global backend change)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout=layout, dpi=dpi)
    FigureCanvasAgg(fig)
    return fig


def _panel_size(box, area: float) -> tuple[float, float]:
    """Width and height [in] of a panel of the given area with the box's aspect ratio."""
    aspect = (box[3] - box[2]) / (box[1] - box[0])
    width = math.sqrt(area / aspect)
    width = min(max(width, 1.6), 6.0)
    return width, min(max(width * aspect, 1.6), 7.0)


def _suptitle(fig, title: str, fontsize: float) -> None:
    """Figure title wrapped to the figure's width (a narrow GIF frame would cut it)."""
    chars = int(fig.get_figwidth() * 72 / (0.55 * fontsize))  # ~ average glyph width
    fig.suptitle(textwrap.fill(title, max(chars, 20)), fontsize=fontsize)


def _lay_out_once(fig) -> None:
    """Constrained layout computed once, not on every frame: twice as fast, and the axes
    do not jitter as the labels change."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    ConstrainedLayoutEngine(compress=True).execute(fig)


def _draw_bodies(ax, polygons, colours, box):
    """Bodies as one PolyCollection on an equal-aspect axis with the shared limits."""
    from matplotlib.collections import PolyCollection

    bodies = PolyCollection(polygons, facecolors=colours, edgecolors=EDGE_COLOUR, linewidths=0.6)
    ax.add_collection(bodies)
    ax.set_xlim(box[0], box[1])
    ax.set_ylim(box[2], box[3])
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.tick_params(labelsize=7)
    return bodies


def snapshot_strip(ds, path, times=None, n: int = 6, title: str | None = None) -> Path:
    """Write a PNG: one row of panels showing the case at n times (or at ``times`` [s]).

    Default times are evenly spread over the run, first and last sample included (the
    last one at the collapse if the case collapsed). Every panel has the same limits.
    """
    ds = _as_case(ds)
    path = _output_path(path, ".png", "-o")
    samples = snapshot_samples(ds, times, n)
    local = body_polygons(ds)
    time, x, y, theta = _histories(ds)
    box = view_box(local, x, y, theta, structure_bodies(ds))
    colours = body_colours(ds)
    base = _base_displacement(ds)
    end = collapse_time(ds)

    width, height = _panel_size(box, PANEL_AREA)
    # 'compressed' is constrained layout for fixed-aspect axes; the extra height holds
    # the suptitle, the two-line panel titles and the x labels
    fig = _figure(width * len(samples), height + DECORATION_HEIGHT, layout="compressed")
    axes = fig.subplots(1, len(samples), squeeze=False)[0]
    for ax, i in zip(axes, samples):
        _draw_bodies(ax, posed_polygons(local, x[i], y[i], theta[i]), colours, box)
        ax.set_title(panel_label(time, base, i, end), fontsize=9)
    axes[0].set_ylabel("y [m]")
    _suptitle(fig, title if title is not None else default_title(ds), fontsize=10)
    write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png",
                                                    bbox_inches="tight"))  # trim spare margin
    return path


def animate(ds, path, fps: float = 20, max_frames: int = 300, every: float | None = None,
            progress: bool | None = None, title: str | None = None) -> Path:
    """Write an animated GIF of the case: one frame per sample, at most max_frames.

    every: simulated time between frames [s] (default: as many samples as max_frames
    allows); progress: a frame counter on stderr (default: only when stderr is a terminal).
    """
    ds = _as_case(ds)
    path = _output_path(path, ".gif", "-o")
    fps = _positive(fps, "--fps")
    max_frames = _whole_at_least_one(max_frames, "--max-frames")
    local = body_polygons(ds)
    time, x, y, theta = _histories(ds)
    step = None
    if every is not None:
        interval = float(time[1] - time[0]) if len(time) > 1 else 1.0
        step = max(1, round(_positive(every, "--every") / interval))
    frames = frame_samples(len(time), max_frames, step)
    box = view_box(local, x, y, theta, structure_bodies(ds))
    base = _base_displacement(ds)

    width, height = _panel_size(box, FRAME_AREA)
    fig = _figure(width, height + DECORATION_HEIGHT, layout=None, dpi=GIF_DPI)
    ax = fig.subplots()
    bodies = _draw_bodies(ax, posed_polygons(local, x[0], y[0], theta[0]), body_colours(ds), box)
    ax.set_ylabel("y [m]")
    end = collapse_time(ds)
    label = ax.set_title(panel_label(time, base, 0, end), fontsize=10)
    _suptitle(fig, title if title is not None else default_title(ds), fontsize=8)
    _lay_out_once(fig)

    def write(tmp):
        writer = _gif_writer(fps)
        show = sys.stderr.isatty() if progress is None else progress
        with writer.saving(fig, tmp, dpi=GIF_DPI):
            for k, i in enumerate(frames):
                bodies.set_verts(posed_polygons(local, x[i], y[i], theta[i]))
                label.set_text(panel_label(time, base, i, end))
                writer.grab_frame()
                if show:
                    print(f"\r  frame {k + 1}/{len(frames)}", end="", file=sys.stderr)
        if show:
            print(file=sys.stderr)

    write_atomically(path, write)
    return path


def _gif_writer(fps: float):
    """A PillowWriter keeping each frame in 256 colours: a third of the memory of RGB frames.

    The GIF stores 256 colours per frame anyway, so the picture is the same.
    """
    from matplotlib.animation import PillowWriter
    from PIL import Image

    class PaletteFramesWriter(PillowWriter):
        def grab_frame(self, **savefig_kwargs):
            super().grab_frame(**savefig_kwargs)
            frames = getattr(self, "_frames", None)  # PillowWriter's frame list, if it has one
            if frames and frames[-1].mode == "RGB":
                frames[-1] = frames[-1].convert("P", palette=Image.Palette.ADAPTIVE, colors=256)

    return PaletteFramesWriter(fps=fps)


# --- files --------------------------------------------------------------------------------

def _output_path(path, suffix: str, field: str, case=None) -> Path:
    from stonedem.entry import check_output_path

    path = Path(path)
    if path.suffix.lower() != suffix:
        raise InputError(field, f"'{path}' does not end in {suffix}", f"name the output *{suffix}")
    return check_output_path(path, field, inputs=[case] if case is not None else [])


def _positive(value, field: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
        raise InputError(field, f"must be a number > 0, got {value!r}", "give a positive value")
    return float(value)


def _whole_at_least_one(value, field: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InputError(field, f"must be a whole number >= 1, got {value!r}", "give e.g. 300")
    return int(value)


# --- command line -------------------------------------------------------------------------

def add_parser(subparsers) -> None:
    """Add ``stonedem snapshots`` and ``stonedem animate`` to a parser's subcommands.

    Each sets ``handler``, a function of the parsed arguments returning the exit status
    (it raises InputError on bad input, which stonedem's main prints and turns into exit 2).
    """
    strip = subparsers.add_parser("snapshots", help="draw a case at several times (one PNG strip)")
    strip.add_argument("case", type=Path, help="case dataset (.nc from stonedem run)")
    strip.add_argument("-o", "--output", type=Path, default=None,
                       help="output PNG (default: CASE_snapshots.png beside the case)")
    strip.add_argument("-n", type=int, default=6,
                       help="number of panels, evenly spread (default 6)")
    strip.add_argument("--times", type=float, nargs="+", default=None, metavar="T",
                       help="draw at these times [s] instead (nearest samples)")
    strip.add_argument("--title", default=None, help="figure title (default: from the dataset)")
    strip.set_defaults(handler=command_snapshots)

    movie = subparsers.add_parser("animate", help="animate a case (GIF)")
    movie.add_argument("case", type=Path, help="case dataset (.nc from stonedem run)")
    movie.add_argument("-o", "--output", type=Path, default=None,
                       help="output GIF (default: CASE.gif beside the case)")
    movie.add_argument("--fps", type=float, default=20.0, help="frames per second (default 20)")
    movie.add_argument("--max-frames", type=int, default=300,
                       help="at most this many frames (default 300)")
    movie.add_argument("--every", type=float, default=None, metavar="DT",
                       help="simulated time between frames [s] (default: spread over --max-frames)")
    movie.add_argument("--title", default=None, help="figure title (default: from the dataset)")
    movie.set_defaults(handler=command_animate)


def command_snapshots(args) -> int:
    out = args.output or args.case.with_name(f"{args.case.stem}_snapshots.png")
    _output_path(out, ".png", "-o", args.case)  # refuse a bad name before reading the case
    ds = open_case(args.case)
    snapshot_strip(ds, out, times=args.times, n=args.n, title=args.title)
    print(f"wrote {out}", file=sys.stderr)
    return 0


def command_animate(args) -> int:
    out = args.output or args.case.with_suffix(".gif")
    _output_path(out, ".gif", "-o", args.case)
    ds = open_case(args.case)
    animate(ds, out, fps=args.fps, max_frames=args.max_frames, every=args.every, title=args.title)
    print(f"wrote {out}", file=sys.stderr)
    return 0


def main(argv: list[str] | None = None) -> int:
    """``snapshots ...`` or ``animate ...`` on their own; errors as one line, exit 2."""
    from stonedem.entry import Parser

    parser = Parser(prog="stonedem", description="pictures of a stonedem case dataset")
    add_parser(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(argv)
    from stonedem.entry import guarded

    return guarded(lambda: args.handler(args))


def main_animate(argv: list[str] | None = None) -> int:
    """``stonedem animate`` with its arguments (without the word animate)."""
    return main(["animate", *(sys.argv[1:] if argv is None else argv)])


def main_snapshots(argv: list[str] | None = None) -> int:
    """``stonedem snapshots`` with its arguments (without the word snapshots)."""
    return main(["snapshots", *(sys.argv[1:] if argv is None else argv)])
