"""Pictures of a simulated case from its dataset alone: a strip of snapshots and a GIF.

A case dataset (``stonedem run``) holds the centroid histories ``x``, ``y``, ``theta`` of every
body and the full scene as JSON in ``attrs["scene"]``. The body outlines are rebuilt from
that scene with the scene loader itself (:func:`stonedem.engine.scene.scene_from_dict`), so the
pictures show exactly the polygons the engine simulated.

``stonedem snapshots CASE.nc [-o OUT.png] [-n 6] [--times 0 1 2]`` and
``stonedem animate CASE.nc [-o OUT.gif] [--fps 20] [--max-frames 300]``. Outputs are written to
a temporary file beside the target and renamed, so bad input leaves no file behind.

Every option and every field of the dataset the drawing reads is checked before anything is
drawn, and bad input is refused in one line naming the field (exit 2), creating no file and
no folder: ``-n`` from 1 to MAX_PANELS, ``--times`` finite, inside the run and at most
MAX_PANELS of them, ``--fps`` from FPS_RANGE, ``--max-frames`` from 1 to MAX_FRAMES,
``--every`` finite, > 0 and at most the run's length, ``--title`` printable and at most
MAX_TITLE characters; the file a readable NetCDF dataset holding ``x``, ``y``, ``theta``
on (time, body) and nothing else, numeric and finite (a run stonedem wrote never holds a
non-finite position: a diverged run is refused, so NaN or infinite positions mean a damaged
or foreign file and are refused, not skipped), ``time`` finite and increasing, ``body_role``
on (body), ``attrs.scene`` a JSON mapping that the scene loader accepts with the dataset's
bodies. The options are declared once, as the :mod:`stonedem.io.spec` rows
:data:`SNAPSHOT_OPTIONS` and :data:`ANIMATE_OPTIONS`, the dataset's variables in the table
:data:`CASE_VARIABLES`. Titles are plain text: a ``$`` is drawn as a dollar sign, never
read as TeX.

matplotlib is used through its object API on an Agg canvas (no pyplot, no global backend
switch), and xarray and matplotlib are imported only when drawing, so ``stonedem --help`` stays
quick.
"""

from __future__ import annotations

import json
import math
import stat
import sys
import textwrap
from pathlib import Path

import numpy as np

from stonedem.errors import InputError, one_line
from stonedem.io.atomic import write_atomically
from stonedem.io.spec import Field, Spec
from stonedem.options import checked

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

# ranges of the options (the strip is one row of panels; every GIF frame is kept in memory
# until the file is written, ~0.2 MB each)
MAX_PANELS = 20
MAX_FRAMES = 1000
FPS_RANGE = (0.1, 50.0)  # [1/s]: GIF delays are whole 1/100 s, from 2/100 s to 10 s here
MAX_TITLE = 300  # characters
# a stonedem dataset's positions stay within a few structure sizes of the origin; beyond
# these a file is damaged (and the drawing would overflow)
MAX_POSITION = 1.0e6  # [m]
MAX_ROTATION = 1.0e6  # [rad]


# --- reading a case -----------------------------------------------------------------------


def open_case(path: str | Path):
    """A stonedem case dataset read into memory and checked, or an InputError naming the fix."""
    import xarray as xr

    path = check_case_path(path)
    try:
        # stored numbers as they are: no CF time decoding of a foreign file's units
        with xr.open_dataset(path, decode_times=False, decode_timedelta=False) as ds:
            ds = ds.load()
    except (KeyboardInterrupt, MemoryError):
        raise
    except Exception:  # noqa: BLE001 - whatever a foreign or damaged file makes the backends raise
        raise InputError(
            str(path),
            "not a readable NetCDF dataset",
            "give a case dataset written by stonedem run",
        ) from None
    check_case(ds, str(path))
    return ds


def check_case_path(path: str | Path) -> Path:
    """The case path when it names an existing regular file, else an InputError."""
    path = Path(path)
    problem, fix = None, "give a case dataset (.nc from stonedem run)"
    if not str(path).isprintable():
        problem, fix = "contains control characters", "give a plain path"
    else:
        try:
            mode = path.stat().st_mode
        except FileNotFoundError:
            problem, fix = "case file not found", "check the path (a .nc file from stonedem run)"
        except OSError as err:  # a name too long, a loop of links, a folder without access
            problem = f"cannot be read ({err.strerror})"
            fix = "check the path (a .nc file from stonedem run)"
        else:
            if stat.S_ISDIR(mode):
                problem = "is a folder, not a case file"
            elif not stat.S_ISREG(mode):
                problem = "not a regular file"
    if problem:
        raise InputError(one_line(str(path), 200), problem, fix)
    return path


# the variables the drawings read: their dimensions (two in either order; () a scalar) and
# the largest |value| a stonedem run writes (None: not checked as finite, only as numbers)
CASE_VARIABLES = {
    "x": (("time", "body"), MAX_POSITION),
    "y": (("time", "body"), MAX_POSITION),
    "theta": (("time", "body"), MAX_ROTATION),
    "time": (("time",), math.inf),
    "body": (("body",), None),
    "body_role": (("body",), None),
    "base_displacement": (("time",), math.inf),  # the optional ones from here
    "collapsed": ((), None),
    "collapse_time": ((), None),
}
NUMERIC = ("time", *REQUIRED_VARIABLES, "base_displacement", "collapsed", "collapse_time")


def check_case(ds, where: str = "dataset") -> None:
    """Refuse a dataset lacking what the drawings need, or holding it in another shape.

    Checked (:data:`CASE_VARIABLES`): the histories ``x``, ``y``, ``theta`` on (time, body)
    only, numeric, finite and within MAX_POSITION / MAX_ROTATION; ``time`` on (time), finite
    and increasing; ``body`` and ``body_role`` on (body); ``base_displacement``, ``collapsed``
    and ``collapse_time`` when present; ``attrs.scene`` a JSON mapping the scene loader
    accepts, whose bodies are the dataset's. Each refusal names the field.
    """
    problem = next(_case_problems(ds), None)
    if problem is not None:
        name, text = problem
        field = f"{where}: {name}" if name else where
        raise InputError(field, text, "give a dataset written by stonedem run")
    body_polygons(ds, where)  # the scene loader's verdict on attrs.scene


def _case_problems(ds):
    """(variable, problem) for each way ``ds`` fails :func:`check_case`, in the order checked;
    the first one is the refusal (a later check may rely on the earlier ones)."""
    variables = getattr(ds, "variables", None)
    if variables is None:
        yield "", "not an xarray Dataset"
        return
    for name in REQUIRED_VARIABLES + REQUIRED_COORDS:
        if name not in variables:
            yield name, "missing, so this is not a stonedem case dataset"
    for name, (dims, _) in CASE_VARIABLES.items():
        shape = tuple(ds[name].dims) if name in variables else dims
        if sorted(shape) != sorted(dims):
            yield name, f"has dimensions {shape}, expected {dims or 'a scalar'}"
    if ds.sizes["time"] < 1:
        yield "time", "no samples"
    if ds.sizes["body"] < 1:
        yield "body", "no bodies"
    values = {}
    for name in (n for n in NUMERIC if n in variables):
        dims, bound = CASE_VARIABLES[name]
        raw = ds[name].transpose(*dims).values
        if raw.dtype.kind not in "biuf":
            yield name, f"holds {raw.dtype} values, not numbers"
        values[name] = value = np.asarray(raw, dtype=float)
        if bound is not None and not np.all(np.isfinite(value)):
            bad = ~np.isfinite(value)
            first = _first_bad(ds, name, bad, values["time"])
            yield name, f"{int(bad.sum())} non-finite values ({first}); stonedem never writes one"
        if bound is not None and np.abs(value).max() > bound:
            yield name, f"holds values beyond +-{bound:g} (a damaged file)"
        if name == "time" and len(value) > 1 and not np.all(np.diff(value) > 0):
            yield name, "is not increasing"
    time = values["time"]
    if "collapsed" in values and float(values["collapsed"]) not in (0.0, 1.0):
        yield "collapsed", f"must be 0 or 1, got {float(values['collapsed']):g}"
    end = float(values.get("collapse_time", math.nan))
    slack = 0.5 * (time[1] - time[0]) if len(time) > 1 else 0.0
    if math.isfinite(end) and not (time[0] - slack <= end <= time[-1] + slack):
        yield "collapse_time", f"{end:g} s is outside the run ({time[0]:g} to {time[-1]:g} s)"


def _first_bad(ds, name: str, bad: np.ndarray, time: np.ndarray) -> str:
    """Where the first non-finite value of a variable lies, for a message."""
    index = np.argwhere(bad)[0]
    if name == "time":
        return f"the first at sample {index[0]}"
    at = f"at t = {time[index[0]]:g} s"
    if len(index) > 1:
        return f"the first of body {_shown(ds['body'].values[index[1]])} {at}"
    return f"the first {at}"


def _shown(value) -> str:
    return one_line(str(value), 60)


def _as_case(case):
    """Accept a dataset or the path of one."""
    if isinstance(case, (str, Path)):
        return open_case(case)
    check_case(case)
    return case


def body_polygons(ds, where: str = "dataset") -> list[np.ndarray]:
    """Local vertices (n_i, 2) [m] about each centroid, in the dataset's body order.

    Rebuilt from ``attrs["scene"]`` by the scene loader. The excitation is replaced by
    none first: the outlines do not depend on it, and a record file may not exist here.
    """
    from stonedem.engine.scene import scene_from_dict

    field = f"{where}: attrs.scene"
    spec = _scene_spec(ds, where)
    spec["excitation"] = {"kind": "none"}
    problem = None
    try:
        scene = scene_from_dict(spec)
    except InputError as err:
        field, problem = f"{field}.{err.field}", err.problem
    except (
        TypeError,
        ValueError,
        KeyError,
        AttributeError,
        IndexError,
        OverflowError,
        RecursionError,
    ) as err:
        problem = f"not a scene the loader accepts ({type(err).__name__})"
    else:
        if scene.body_names != [str(b) for b in ds["body"].values]:
            field = f"{where}: body"
            problem = "the dataset's bodies differ from those of its scene"
    if problem:
        raise InputError(field, problem, "re-run the case with stonedem run")
    return [body.vertices - body.centroid for body in scene.bodies]


def _scene_spec(ds, where: str = "dataset") -> dict:
    """``attrs["scene"]`` read as a JSON mapping, or an InputError naming it."""
    text, spec = ds.attrs.get("scene"), None
    if "scene" not in ds.attrs:
        problem = "missing, so the body outlines cannot be rebuilt"
    elif not isinstance(text, (str, bytes)):
        problem = f"a {type(text).__name__}, not JSON text"
    else:
        try:
            spec = json.loads(text)
        except (TypeError, ValueError, RecursionError):
            problem = "not valid JSON"
        else:
            problem = (
                None if isinstance(spec, dict) else f"JSON {type(spec).__name__}, not a mapping"
            )
    if problem:
        raise InputError(
            f"{where}: attrs.scene",
            problem,
            "re-run the case with stonedem run (it stores the scene as JSON)",
        )
    return spec


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
    if "collapsed" not in ds or not float(ds["collapsed"]):
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
        n = check_panels(n)
        end = collapse_time(ds)
        targets = np.linspace(time[0], time[-1] if end is None else end, n)
    else:
        targets = check_times(times)
        _check_times(targets, time)
    nearest = np.abs(time[None, :] - targets[:, None]).argmin(axis=1)
    _, first = np.unique(nearest, return_index=True)
    return nearest[np.sort(first)]  # in the order asked, each sample once


def _check_times(targets: np.ndarray, time: np.ndarray) -> None:
    """Every asked time inside the run (half a sample of slack at each end)."""
    slack = 0.5 * (time[1] - time[0]) if len(time) > 1 else 0.0
    run = f"[{float(time[0] - slack)!r}, {float(time[-1] + slack)!r}]"  # repr: the exact floats
    hint = f"give times inside the run, from {time[0]:g} to {time[-1]:g} s"
    Field("--times", "numbers", units="s", range=run, hint=hint).check(targets.tolist())


def _frame_step(every: float, time: np.ndarray) -> int:
    """Samples between frames for ``--every`` [s]; refused when longer than the run."""
    if len(time) < 2:
        return 1
    span = float(time[-1] - time[0])
    hint = f"give a time step of at most the run's length, {span:g} s"
    Field("--every", units="s", range=f"(0, {span!r}]", hint=hint).check(every)
    interval = span / (len(time) - 1)  # mean sample interval (stonedem samples evenly)
    return max(1, round(every / interval))


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
        c, s = np.cos(theta[:, i : i + 1]), np.sin(theta[:, i : i + 1])
        wx = x[:, i : i + 1] + c * verts[:, 0] - s * verts[:, 1]
        wy = y[:, i : i + 1] + s * verts[:, 0] + c * verts[:, 1]
        lo = np.minimum(lo, [np.nanmin(wx), np.nanmin(wy)])
        hi = np.maximum(hi, [np.nanmax(wx), np.nanmax(wy)])
    return lo, hi


# --- titles -------------------------------------------------------------------------------


def default_title(ds) -> str:
    """'name: structure; excitation[; collapsed at t s]' from the dataset's attributes.

    Plain text, never refused: a field the title cannot read (an excitation of another
    program, say) is left out of it."""
    scene = _scene_spec(ds)
    parts = [structure_label(scene, [str(r) for r in ds["body_role"].values])]
    parts.append(_excitation_text(_json_attr(ds, "excitation") or scene.get("excitation") or {}))
    end = collapse_time(ds)
    if end is not None:
        parts.append(f"collapsed at {end:.2f} s")
    name = scene.get("name")
    return (f"{one_line(str(name), 120)}: " if name not in (None, "") else "") + "; ".join(parts)


def _excitation_text(desc) -> str:
    from stonedem.motion.excitation import excitation_label  # numba: only when drawing

    if not isinstance(desc, dict):
        return "base motion unknown"
    try:
        return one_line(excitation_label(desc), 200)
    except (TypeError, ValueError, KeyError, AttributeError, IndexError, OverflowError):
        return "base motion unknown"


def _json_attr(ds, key):
    try:
        return json.loads(ds.attrs[key])
    except (KeyError, TypeError, ValueError, RecursionError):
        return None


def _number(value) -> str:
    """A scene value as '%g' when it is a number (or a numeric string), else as given."""
    try:
        return f"{float(value):g}"
    except (TypeError, ValueError, OverflowError):
        return one_line(str(value), 40)


def structure_label(scene: dict, roles: list[str]) -> str:
    """E.g. 'column, 4 drums, 6 x 1 m', 'colonnade, 3 columns x 2 drums, epistyle a' or,
    for a scene of listed bodies, '1 block on the base'."""
    spec = scene.get("structure")
    if not isinstance(spec, dict):
        counts = {role: roles.count(role) for role in dict.fromkeys(roles) if role != "base"}
        text = ", ".join(
            f"{k} {one_line(role, 40)}{'s' if k > 1 else ''}" for role, k in counts.items()
        )
        return text + (" on the base" if "base" in roles else "")
    kind = one_line(str(spec.get("kind", "structure")), 40)
    words = [kind.replace("_", " ")]
    if "n_columns" in spec:
        drums = _number(spec.get("n_drums", 1))
        words.append(f"{_number(spec['n_columns'])} columns x {drums} drums")
    elif "n_drums" in spec:
        words.append(f"{_number(spec['n_drums'])} drums")
    if "height" in spec or "width" in spec:
        words.append(f"{_number(spec.get('height', 6.0))} x {_number(spec.get('width', 1.0))} m")
    if "epistyle_type" in spec:
        words.append(f"epistyle {_number(spec['epistyle_type'])}")
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
    """Figure title wrapped to the figure's width (a narrow GIF frame would cut it), as
    plain text: ``$...$`` is not mathtext, no TeX is run."""
    chars = int(fig.get_figwidth() * 72 / (0.55 * fontsize))  # ~ average glyph width
    fig.suptitle(textwrap.fill(title, max(chars, 20)), fontsize=fontsize, **PLAIN_TEXT)


# every text of a picture: drawn as given (no mathtext, no LaTeX whatever matplotlibrc says)
PLAIN_TEXT = {"parse_math": False, "usetex": False}


def _plain_rc():
    """rcParams for the drawing: no LaTeX for the tick labels either."""
    import matplotlib

    return matplotlib.rc_context({"text.usetex": False})


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
    Everything is checked (:func:`check_strip_options`, the output path, :func:`check_case`)
    before anything is drawn.
    """
    times, n, title = check_strip_options(times, n, title)
    path = _output_path(path, ".png", "-o", ds if isinstance(ds, (str, Path)) else None)
    return _strip(_as_case(ds), path, times, n, title)


def check_strip_options(times=None, n: int = 6, title: str | None = None):
    """(times, n, title) of a strip, checked without the dataset; InputError otherwise."""
    return (None if times is None else check_times(times)), check_panels(n), check_title(title)


def _strip(ds, path: Path, times, n: int, title: str | None) -> Path:
    """The strip of a checked dataset and checked options."""
    samples = snapshot_samples(ds, times, n)
    title = title if title is not None else default_title(ds)
    local = body_polygons(ds)
    time, x, y, theta = _histories(ds)
    box = view_box(local, x, y, theta, structure_bodies(ds))
    colours = body_colours(ds)
    base = _base_displacement(ds)
    end = collapse_time(ds)

    with _plain_rc():
        width, height = _panel_size(box, PANEL_AREA)
        # 'compressed' is constrained layout for fixed-aspect axes; the extra height holds
        # the suptitle, the two-line panel titles and the x labels
        fig = _figure(width * len(samples), height + DECORATION_HEIGHT, layout="compressed")
        axes = fig.subplots(1, len(samples), squeeze=False)[0]
        for ax, i in zip(axes, samples):
            _draw_bodies(ax, posed_polygons(local, x[i], y[i], theta[i]), colours, box)
            ax.set_title(panel_label(time, base, i, end), fontsize=9, **PLAIN_TEXT)
        axes[0].set_ylabel("y [m]")
        _suptitle(fig, title, fontsize=10)
        write_atomically(
            path, lambda tmp: fig.savefig(tmp, dpi=110, format="png", bbox_inches="tight")
        )  # trim spare margin
    return path


def animate(
    ds,
    path,
    fps: float = 20,
    max_frames: int = 300,
    every: float | None = None,
    progress: bool | None = None,
    title: str | None = None,
) -> Path:
    """Write an animated GIF of the case: one frame per sample, at most max_frames.

    every: simulated time between frames [s] (default: as many samples as max_frames
    allows); progress: a frame counter on stderr (default: only when stderr is a terminal).
    Everything is checked (:func:`check_animation_options`, the output path,
    :func:`check_case`) before anything is drawn.
    """
    fps, max_frames, every, title = check_animation_options(fps, max_frames, every, title)
    path = _output_path(path, ".gif", "-o", ds if isinstance(ds, (str, Path)) else None)
    return _animation(_as_case(ds), path, fps, max_frames, every, title, progress)


def check_animation_options(
    fps: float = 20, max_frames: int = 300, every: float | None = None, title: str | None = None
):
    """(fps, max_frames, every, title) of an animation, checked without the dataset."""
    return check_fps(fps), check_max_frames(max_frames), check_every(every), check_title(title)


def _animation(
    ds,
    path: Path,
    fps: float,
    max_frames: int,
    every: float | None,
    title: str | None,
    progress: bool | None = None,
) -> Path:
    """The GIF of a checked dataset and checked options."""
    time, x, y, theta = _histories(ds)
    step = None if every is None else _frame_step(every, time)
    frames = frame_samples(len(time), max_frames, step)
    title = title if title is not None else default_title(ds)
    local = body_polygons(ds)
    box = view_box(local, x, y, theta, structure_bodies(ds))
    base = _base_displacement(ds)
    end = collapse_time(ds)

    with _plain_rc():
        width, height = _panel_size(box, FRAME_AREA)
        fig = _figure(width, height + DECORATION_HEIGHT, layout=None, dpi=GIF_DPI)
        ax = fig.subplots()
        bodies = _draw_bodies(
            ax, posed_polygons(local, x[0], y[0], theta[0]), body_colours(ds), box
        )
        ax.set_ylabel("y [m]")
        label = ax.set_title(panel_label(time, base, 0, end), fontsize=10, **PLAIN_TEXT)
        _suptitle(fig, title, fontsize=8)
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


# --- options ------------------------------------------------------------------------------


TITLE = Field(
    "--title",
    "text",
    limit=MAX_TITLE,
    doc=f"figure title, plain text of at most {MAX_TITLE} characters",
)
SNAPSHOT_OPTIONS = Spec(
    (
        Field(
            "-n",
            "integer",
            range=f"[1, {MAX_PANELS}]",
            default=6,
            hint=f"give a whole number from 1 to {MAX_PANELS}, e.g. -n 6",
            doc=f"number of panels, evenly spread, 1 to {MAX_PANELS}",
        ),
        Field(
            "--times",
            "numbers",
            units="s",
            limit=MAX_PANELS,
            hint=f"give 1 to {MAX_PANELS} times in s, e.g. --times 0 1 2",
            doc=f"draw at these times [s] instead (nearest samples; at most {MAX_PANELS}, "
            "inside the run)",
        ),
        TITLE,
    ),
    doc="stonedem snapshots",
)
ANIMATE_OPTIONS = Spec(
    (
        Field(
            "--fps",
            units="frames/s",
            range=f"[{FPS_RANGE[0]!r}, {FPS_RANGE[1]!r}]",
            default=20.0,
            hint=f"give a number from {FPS_RANGE[0]:g} to {FPS_RANGE[1]:g}, e.g. --fps 20",
            doc=f"frames per second, {FPS_RANGE[0]:g} to {FPS_RANGE[1]:g}",
        ),
        Field(
            "--max-frames",
            "integer",
            range=f"[1, {MAX_FRAMES}]",
            default=300,
            hint=f"give a whole number from 1 to {MAX_FRAMES}, e.g. --max-frames 300",
            doc=f"at most this many frames, 1 to {MAX_FRAMES}",
        ),
        Field(
            "--every",
            units="s",
            range="(0, inf)",
            hint="give a finite time > 0 s, e.g. --every 0.05",
            doc="simulated time between frames [s], > 0 and at most the run's length",
        ),
        TITLE,
    ),
    doc="stonedem animate",
)
# what a script may pass for a number option (numpy's too; never text or a bool)
_WHOLE = (int, np.integer)
_REAL = (int, float, np.integer, np.floating)


def check_panels(n) -> int:
    """``-n``: a whole number from 1 to MAX_PANELS."""
    return checked(SNAPSHOT_OPTIONS["-n"], n, _WHOLE)


def check_times(times) -> np.ndarray:
    """``--times``: 1 to MAX_PANELS finite times [s] (whether they fall in the run is checked
    with the dataset)."""
    field = SNAPSHOT_OPTIONS["--times"]
    try:  # a single time or numeric text, as numpy reads them
        times = np.atleast_1d(np.asarray(times, dtype=float)).tolist()
    except (TypeError, ValueError, OverflowError):
        pass  # the kit refuses it as given
    targets = np.asarray(field.check(times), dtype=float)
    if targets.size == 0:
        raise InputError("--times", "no times given", field.hint)
    return targets


def check_fps(fps) -> float:
    """``--fps``: a finite number in FPS_RANGE."""
    return checked(ANIMATE_OPTIONS["--fps"], fps, _REAL)


def check_max_frames(value) -> int:
    """``--max-frames``: a whole number from 1 to MAX_FRAMES."""
    return checked(ANIMATE_OPTIONS["--max-frames"], value, _WHOLE)


def check_every(every) -> float | None:
    """``--every``: None or a finite time > 0 [s] (at most the run's length: checked with the
    dataset)."""
    return None if every is None else checked(ANIMATE_OPTIONS["--every"], every, _REAL)


def check_title(title) -> str | None:
    """``--title``: None or printable text of at most MAX_TITLE characters (drawn as plain text)."""
    return None if title is None else TITLE.check(title)


# --- files --------------------------------------------------------------------------------


def _output_path(path, suffix: str, field: str, case=None) -> Path:
    """The output path, refused before any computing (:func:`stonedem.entry.check_output_path`);
    creates nothing: the folder is made when the picture is written."""
    from stonedem.entry import check_output_path

    path, problem = Path(path), None
    shown = one_line(str(path), 200)
    if not str(path).isprintable():
        problem, fix = f"{shown} contains control characters", "give a plain file name"
    elif path.name.lower() == suffix:  # ".gif" alone: pathlib sees a hidden file, no suffix
        problem, fix = f"'{shown}' has no name before {suffix}", f"give a name such as out{suffix}"
    elif path.suffix.lower() != suffix:
        problem, fix = f"'{shown}' does not end in {suffix}", f"name the output *{suffix}"
    if problem:
        raise InputError(field, problem, fix)
    return check_output_path(path, field, inputs=[case] if case is not None else [])


# --- command line -------------------------------------------------------------------------


def add_parser(subparsers) -> None:
    """Add ``stonedem snapshots`` and ``stonedem animate`` to a parser's subcommands, their
    options from :data:`SNAPSHOT_OPTIONS` and :data:`ANIMATE_OPTIONS`.

    Each sets ``handler``, a function of the parsed arguments returning the exit status
    (it raises InputError on bad input, which stonedem's main prints and turns into exit 2).
    """
    strip = subparsers.add_parser("snapshots", help="draw a case at several times (one PNG strip)")
    strip.add_argument("case", type=Path, help="case dataset (.nc from stonedem run)")
    strip.add_argument(
        "-o",
        "--output",
        type=Path,
        default=None,
        help="output PNG (default: CASE_snapshots.png beside the case)",
    )
    _add_option(strip, SNAPSHOT_OPTIONS["-n"], type=int)
    _add_option(strip, SNAPSHOT_OPTIONS["--times"], "", type=float, nargs="+", metavar="T")
    _add_option(strip, TITLE, "default: from the dataset")
    strip.set_defaults(handler=command_snapshots)

    movie = subparsers.add_parser("animate", help="animate a case (GIF)")
    movie.add_argument("case", type=Path, help="case dataset (.nc from stonedem run)")
    movie.add_argument(
        "-o",
        "--output",
        type=Path,
        default=None,
        help="output GIF (default: CASE.gif beside the case)",
    )
    _add_option(movie, ANIMATE_OPTIONS["--fps"], type=float)
    _add_option(movie, ANIMATE_OPTIONS["--max-frames"], type=int)
    _add_option(
        movie,
        ANIMATE_OPTIONS["--every"],
        "default: spread over --max-frames",
        type=float,
        metavar="DT",
    )
    _add_option(movie, TITLE, "default: from the dataset")
    movie.set_defaults(handler=command_animate)


def _add_option(parser, field: Field, default: str | None = None, **kwargs) -> None:
    """An option declared by ``field``: its default, and its doc as the help, followed by
    ``(default)`` (default: the field's own; "" for none)."""
    if default is None:
        default = f"default {field.shown_default()}"
    text = field.doc + (f" ({default})" if default else "")
    parser.add_argument(field.key, default=field.default, help=text, **kwargs)


def command_snapshots(args) -> int:
    """Options, then the output path, then the dataset are checked; then the strip is drawn."""
    times, n, title = check_strip_options(args.times, args.n, args.title)
    check_case_path(args.case)  # a file: the default output is named after it
    out = args.output or args.case.with_name(f"{args.case.stem}_snapshots.png")
    out = _output_path(out, ".png", "-o", args.case)  # refuse a bad name before reading the case
    ds = open_case(args.case)
    _strip(ds, out, times, n, title)
    print(f"wrote {out}", file=sys.stderr)
    return 0


def command_animate(args) -> int:
    """Options, then the output path, then the dataset are checked; then the GIF is drawn."""
    fps, max_frames, every, title = check_animation_options(
        args.fps, args.max_frames, args.every, args.title
    )
    check_case_path(args.case)
    out = args.output or args.case.with_suffix(".gif")
    out = _output_path(out, ".gif", "-o", args.case)
    ds = open_case(args.case)
    _animation(ds, out, fps, max_frames, every, title)
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
