"""What a script needs: scenes in, datasets out, the study's files opened and checked.

Every function here is also a name of the package itself (``stonedem.run_scene``,
``stonedem.open_cube``, ...), loaded on first use, so ``import stonedem`` stays cheap and
``import stonedem.wall`` never loads the 2D engine. Units are SI throughout (m, s, kg,
rad, m s-2); every dataset carries its units in its variables' attributes.

The command line does the same jobs through these functions (``stonedem run`` is
:func:`load_scene` then :func:`run_scene` then :func:`write_dataset`). Bad input raises
:class:`InputError`, whose message is one line: the field, what is wrong, how to fix it.

>>> import stonedem
>>> ds = stonedem.run_scene("tests/data/scenes/rocking_block.yaml")      # doctest: +SKIP
>>> stonedem.write_dataset(ds, "rocking_block.nc")                        # doctest: +SKIP
"""

from __future__ import annotations

import copy
import dataclasses
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from stonedem.errors import InputError, one_line
from stonedem.io.netcdf import write_dataset
from stonedem.io.spec import plain_number

if TYPE_CHECKING:
    import xarray as xr

    from stonedem.engine.scene import Scene

__all__ = [
    "InputError",
    "load_scene",
    "open_cube",
    "open_fragility",
    "open_ida",
    "open_search",
    "run_scene",
    "run_scenes",
    "run_wall",
    "write_dataset",
]

# The kinds of NetCDF file the project writes, told apart by the start of attrs["title"]
# (each writer sets it): what the file is, who writes it, and the function that opens it.
FILE_KINDS = {
    "cube": (
        "stonedem study cube",
        "a study cube",
        "stonedem.study.cube.combine_cases (snakemake: a study's cube)",
        "open_cube",
    ),
    "search": (
        "stonedem threshold search",
        "a threshold search",
        "stonedem.study.runner.run_search (snakemake: a search study's system)",
        "open_search",
    ),
    "ida": (
        "stonedem IDA cube",
        "an IDA cube",
        "stonedem.fragility.ida.ida_cube (snakemake fragility)",
        "open_ida",
    ),
    "fragility": (
        "stonedem fragility curves",
        "a fragility fits file",
        "stonedem.fragility.fit.fragility_dataset (snakemake fragility)",
        "open_fragility",
    ),
    "scene": (
        "stonedem rigid-block simulation",
        "a rigid-block simulation",
        "stonedem run or stonedem.run_scene",
        None,
    ),
    "wall": (
        "stonedem 3D rigid-block wall pushover",
        "a wall pushover",
        "stonedem wall or stonedem.run_wall",
        None,
    ),
    "validation": ("stonedem validation", "a validation dataset", "stonedem validate", None),
}


def _is_path(source) -> bool:
    return isinstance(source, (str, os.PathLike)) and not isinstance(source, bytes)


def _flag(value, name: str) -> bool:
    """A bool argument (numpy's too), or a TypeError naming it."""
    if not isinstance(value, bool) and type(value).__name__ != "bool_":
        raise TypeError(f"{name}: expected True or False, got {type(value).__name__}")
    return bool(value)


class FrozenSpec(dict):
    """A scene's spec that cannot be changed in place: the provenance a run writes
    (``attrs["scene"]``) is this spec, so a changed one would record a scene that did not
    run. A copy (``copy.deepcopy``, ``dict(...)``) is a plain dict to change and load again."""

    def _refuse(self, *args, **kwargs):
        raise TypeError(
            "scene.spec is read-only: it records what runs; change a copy "
            "(copy.deepcopy(scene.spec)) and load it with stonedem.load_scene"
        )

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = __ior__ = _refuse

    def __deepcopy__(self, memo):
        return copy.deepcopy(_thawed(self), memo)

    def __copy__(self):
        return dict(self)

    def __reduce__(self):
        return (dict, (_thawed(self),))


def _frozen(value):
    if isinstance(value, Mapping):
        return FrozenSpec((k, _frozen(v)) for k, v in value.items())
    if isinstance(value, (list, tuple)):
        return tuple(_frozen(v) for v in value)
    return value


def _thawed(value):
    if isinstance(value, Mapping):
        return {k: _thawed(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_thawed(v) for v in value]
    return value


def _freeze_spec(scene):
    return dataclasses.replace(scene, spec=_frozen(scene.spec))


# --- the 2D engine --------------------------------------------------------------------------


def load_scene(source, *, overrides=None, base_dir=None) -> Scene:
    """A validated scene from a YAML file or a mapping.

    Parameters
    ----------
    source : str, os.PathLike or Mapping
        The path of a scene YAML file, or the scene as a mapping with the same keys (the
        format of docs/guide/scenes.md: ``bodies`` or ``structure``, ``contact``,
        ``excitation``, ``solver``, ...). Lengths in m, masses in kg, angles in rad,
        accelerations in m s-2, times in s. A mapping is copied, never changed.
    base_dir : str or os.PathLike, optional
        Where relative file names of the scene (a record file) are looked up: by default
        the folder of the YAML file, or the working folder for a mapping. Record names
        such as ``northridge_1994_mul009`` are also found in the project's ``records/``.
    overrides : list of str or Mapping, optional
        Fields to set before validation: ``["solver.duration=2"]`` as ``stonedem run
        --set`` takes them (values parsed as YAML), or ``{"solver.duration": 2.0}``
        (values used as given). Dotted keys; list items by index or body name
        (``bodies.block.mass``).

    Returns
    -------
    stonedem.engine.scene.Scene
        The frozen, validated scene; its ``spec`` (the defaulted input, written as the
        run's provenance) is read-only too.

    Raises
    ------
    InputError
        A missing or malformed file, an unknown key, a bad value: the message names the
        dotted field and the fix.

    Examples
    --------
    >>> import stonedem
    >>> scene = stonedem.load_scene("tests/data/scenes/rocking_block.yaml",
    ...                             overrides={"solver.duration": 0.5})
    >>> scene.duration, scene.body_names
    (0.5, ['base', 'block'])
    """
    from stonedem.engine.scene import apply_overrides, scene_from_dict
    from stonedem.engine.scene import load_scene as load_scene_file

    if overrides is not None and not isinstance(overrides, (str, Mapping, list, tuple)):
        raise TypeError(
            "overrides: expected a list of key=value strings or a mapping, got "
            f"{type(overrides).__name__}"
        )
    if base_dir is not None and not _is_path(base_dir):
        raise TypeError(
            f"base_dir: expected a folder path (str or os.PathLike), got {type(base_dir).__name__}"
        )
    if base_dir is not None:
        try:
            folder = Path(base_dir).is_dir()
        except (OSError, ValueError):  # a name too long for the filesystem, a NUL byte
            folder = False
        if not folder:
            raise InputError(
                "base_dir",
                f"{one_line(str(base_dir), 200)} is not a folder",
                "give the folder the scene's relative file names are in",
            )
    if _is_path(source):
        return _freeze_spec(load_scene_file(source, overrides=overrides, base_dir=base_dir))
    if isinstance(source, Mapping):
        spec = _thawed(source)  # a copy, tuples as lists
        apply_overrides(spec, overrides)
        return _freeze_spec(scene_from_dict(spec, base_dir="." if base_dir is None else base_dir))
    raise InputError(
        "scene",
        f"expected a scene file path or a mapping, got {type(source).__name__}",
        "give the path of a scene YAML file or a dict of its keys",
    )


def run_scene(scene_or_source, progress: bool = False) -> xr.Dataset:
    """Simulate a scene and return its self-describing dataset.

    Parameters
    ----------
    scene_or_source : Scene, str, os.PathLike or Mapping
        A scene from :func:`load_scene`, or what :func:`load_scene` takes (a YAML path or
        a mapping; file names in a mapping are looked up from the working folder).
    progress : bool, default False
        Print a progress line to stderr while the kernel runs.

    Returns
    -------
    xarray.Dataset
        Histories on ``time`` [s] and ``body``: centroid ``x``, ``y`` [m] and ``theta``
        [rad], velocities, contact forces, energies [J], the base motion; the response
        measures (``max_rocking`` [rad], ``collapsed``, ``collapse_time`` [s], ...) as
        scalars; the scene as JSON and the run's settings in ``attrs``.

    Raises
    ------
    InputError
        Bad scene input; a request the engine refuses before running (too many steps or
        samples); a run that diverged.

    Examples
    --------
    >>> import stonedem
    >>> ds = stonedem.run_scene({"bodies": [
    ...     {"name": "base", "box": {"width": 2.0, "height": 0.2, "center": [0.0, -0.1]}, "driven":
    True},
    ...     {"name": "block", "box": {"width": 0.2, "height": 1.0, "center": [0.0, 0.5]},
    ...      "tilt": {"angle": 0.05, "about": "bottom_right"}}],
    ...     "solver": {"duration": 0.5}})                                 # doctest: +SKIP
    >>> float(ds.theta.sel(body="block").isel(time=0))  # leaning onto its right corner  # doctest:
    +SKIP -0.05
    """
    from stonedem.engine.run import run_scene as simulate_scene
    from stonedem.engine.scene import Scene

    progress = _flag(progress, "progress")
    scene = scene_or_source if isinstance(scene_or_source, Scene) else load_scene(scene_or_source)
    ds = simulate_scene(scene, progress=progress)
    if _is_path(scene_or_source):  # write_dataset refuses to write over it
        ds.attrs["scene_file"] = str(scene_or_source)
    return ds


def run_scenes(
    scenes_or_sources, device: str = "cpu", threads: int | None = None
) -> list[xr.Dataset]:
    """Simulate many scenes at once: what :func:`run_scene` gives each, their loops run side by
    side.

    Parameters
    ----------
    scenes_or_sources : Scene, str, os.PathLike, Mapping, or an iterable of them
        What :func:`run_scene` takes, one per member; one alone is a single member.
    device : {"cpu", "gpu"}, default "cpu"
        ``cpu``: one thread per member on the CPU's cores, each run bit for bit
        :func:`run_scene`'s. ``gpu``: one CUDA thread per member on an NVIDIA GPU (the
        ``[gpu]`` extra); the members must then share a structure (records may differ), and
        runs agree with the CPU's to rounding over a short horizon, in their verdicts over a
        whole record.
    threads : int, optional
        CPU threads (default: all Numba has).

    Returns
    -------
    list of xarray.Dataset
        One dataset per member, as :func:`run_scene` returns it, ``attrs["device"]`` saying
        where it ran.

    Raises
    ------
    TypeError
        ``scenes_or_sources`` is neither a scene nor an iterable of scenes (None, a number).
    InputError
        Bad scene input, an unknown device, members of different structures on the GPU.
    RuntimeError
        ``device="gpu"`` where no GPU can run the loop (the message says why).
    """
    from stonedem.engine.run import run_scenes as simulate_scenes
    from stonedem.engine.scene import Scene

    given = scenes_or_sources
    if isinstance(given, Scene) or _is_path(given) or isinstance(given, Mapping):
        given = [given]  # one scene, not the characters of its path or the keys of its mapping
    else:
        try:  # a 0-d array claims to be iterable and is not
            given = (
                list(given)
                if isinstance(given, Iterable) and not isinstance(given, bytes)
                else None
            )
        except TypeError:
            given = None
        if given is None:
            raise TypeError(
                f"scenes: expected a scene, a scene file path, a mapping or a list of them, "
                f"got {type(scenes_or_sources).__name__}"
            )
    scenes = []
    for i, s in enumerate(given):
        if not (isinstance(s, Scene) or _is_path(s) or isinstance(s, Mapping)):
            raise TypeError(
                f"scenes[{i}]: expected a scene, a scene file path or a mapping, got "
                f"{type(s).__name__}"
            )
        scenes.append(s if isinstance(s, Scene) else load_scene(s))
    if not isinstance(device, str):
        raise TypeError(f"device: expected 'cpu' or 'gpu', got {type(device).__name__}")
    if threads is not None:
        threads = plain_number(threads)
        if isinstance(threads, bool) or not isinstance(threads, int):
            raise TypeError(
                f"threads: expected a whole number or None, got {type(threads).__name__}"
            )
    datasets = simulate_scenes(scenes, device=device, threads=threads)
    for source, ds in zip(given, datasets):
        if _is_path(source):
            ds.attrs["scene_file"] = str(source)
    return datasets


# --- the 3D wall solver ---------------------------------------------------------------------


def run_wall(case, limit_analysis: bool = False, progress: bool = False) -> xr.Dataset:
    """The pushover of a 3D rigid-block masonry wall.

    Parameters
    ----------
    case : str, os.PathLike or Mapping
        A wall case YAML file (the cases of ``config/walls/``) or its mapping: ``panel``
        (block sizes ``a``, ``b``, ``s`` [m], ``blocks_per_course``, ``courses``,
        ``unit_weight`` [N m-3]), ``joints`` (``mu`` [1], ``k_n``, ``k_t`` [N m-3]),
        ``restraints`` and ``load``; schema in :mod:`stonedem.wall.case`.
    limit_analysis : bool, default False
        Also the collapse multiplier by limit analysis on the joint caps at the pushover's
        peak (variable ``lambda_limit_analysis``), as ``stonedem wall --limit``.
    progress : bool, default False
        Log a progress line to stderr every 2 s of a long run.

    Returns
    -------
    xarray.Dataset
        The pushover curve on ``step``: load factor ``lambda`` [1, or Pa for a pressure
        load] and ``control_displacement`` [m]; ``lambda_max``, the ``damage`` state of every
        interface per step, block displacements at the limit; the case in ``attrs``.

    Raises
    ------
    InputError
        A missing or malformed case, a field out of range, a problem too large, a wall
        that is a mechanism under its own weight.

    Examples
    --------
    >>> import stonedem
    >>> ds = stonedem.run_wall("config/walls/free_standing.yaml")         # doctest: +SKIP
    >>> round(float(ds.lambda_max), 3)                                     # doctest: +SKIP
    0.066
    """
    from stonedem.wall.case import check_case, read_case
    from stonedem.wall.cli import pushover

    limit_analysis, progress = _flag(limit_analysis, "limit_analysis"), _flag(progress, "progress")
    if _is_path(case):
        path = Path(case)
        checked = check_case(read_case(path), name=path.stem, where=str(path))
    elif isinstance(case, Mapping):
        checked = check_case(_thawed(case))
    else:
        raise InputError(
            "case",
            f"expected a wall case file path or a mapping, got {type(case).__name__}",
            "give the path of a wall case YAML file (config/walls/) or a dict of its keys",
        )
    return pushover(checked, progress=progress, limit_analysis=limit_analysis)


# --- the study's files ----------------------------------------------------------------------


def file_kind(ds) -> str | None:
    """Which of the project's files a dataset is (a key of ``FILE_KINDS``), from the start of
    its ``title`` attribute; None for a file the project did not write."""
    title = str(ds.attrs.get("title", ""))
    return next(
        (kind for kind, (start, *_rest) in FILE_KINDS.items() if title.startswith(start)), None
    )


def _open(path, kind: str):
    """The file at ``path`` read into memory, if it is a ``kind`` file; else an InputError."""
    import xarray as xr

    _, what, writer, _ = FILE_KINDS[kind]
    if not _is_path(path):
        raise InputError(
            "path",
            f"expected a file path, got {type(path).__name__}",
            f"give the path of {what} (.nc)",
        )
    path = Path(path)
    try:
        path.stat()
    except FileNotFoundError:
        raise InputError(
            str(path), "file not found", f"check the path, or write {what} with {writer}"
        ) from None
    except (OSError, ValueError) as err:  # a name too long, a symlink loop, a NUL byte
        cause = getattr(err, "strerror", None) or str(err)
        raise InputError(
            str(path), f"cannot be read ({cause})", f"give the path of {what} (.nc)"
        ) from None
    if not path.is_file():
        raise InputError(str(path), "is not a regular file", f"give the path of {what} (.nc)")
    try:
        with xr.open_dataset(path) as ds:
            ds = ds.load()
    except (OSError, ValueError, RuntimeError):
        raise InputError(
            str(path), "not a NetCDF file", f"give {what} (.nc) written by {writer}"
        ) from None
    found = file_kind(ds)
    if found != kind:
        if found is None:
            raise InputError(
                str(path),
                f"is not {what} (title {str(ds.attrs.get('title', ''))[:60]!r})",
                f"give {what} written by {writer}",
            )
        _, found_what, _, opener = FILE_KINDS[found]
        fix = (
            f"open it with stonedem.{opener}, or give {what}"
            if opener
            else f"give {what} written by {writer}"
        )
        raise InputError(str(path), f"is {found_what}, not {what}", fix)
    return ds


def open_cube(path) -> xr.Dataset:
    """A study cube, read into memory: each case's measures on the swept parameters.

    Parameters
    ----------
    path : str or os.PathLike
        A cube written by :func:`stonedem.study.cube.combine_cases` (a grid study) or
        :func:`stonedem.study.cube.combine_searches` (a threshold-search study), as the
        workflow writes one per study.

    Returns
    -------
    xarray.Dataset
        One dimension per swept parameter (``pga`` [m s-2], ``n_drums``, ``record``, ...),
        ``time`` [s] for the histories; measures such as ``collapsed`` [1] and
        ``max_rocking`` [rad]. A search study's cube has a ``run`` dimension instead, its
        searched values a coordinate.

    Raises
    ------
    InputError
        The file is missing, not NetCDF, or another kind of file (the message names the
        function that opens it).
    """
    return _open(path, "cube")


def open_search(path) -> xr.Dataset:
    """One system's threshold search, read into memory.

    Parameters
    ----------
    path : str or os.PathLike
        A search file written by :func:`stonedem.study.runner.run_search`
        (:func:`stonedem.study.cube.search_dataset`), as the workflow writes one per
        system of a search study.

    Returns
    -------
    xarray.Dataset
        Every run on ``run`` (sorted by the searched value, e.g. ``pga`` [m s-2], a
        coordinate): its measures (``collapsed``, ``max_rocking`` [rad], ...) and
        ``search_phase``; the bracket: ``collapse_threshold`` (smallest collapse) and
        ``survived_below_threshold``, ``bracket_width`` [1], ``search_status``.

    Raises
    ------
    InputError
        The file is missing, not NetCDF, or another kind of file.
    """
    return _open(path, "search")


def open_ida(path) -> xr.Dataset:
    """An IDA cube, read into memory: the intensity at each limit state per structure and record.

    Parameters
    ----------
    path : str or os.PathLike
        A cube written by :func:`stonedem.fragility.ida.ida_cube`, as ``snakemake
        fragility`` writes it.

    Returns
    -------
    xarray.Dataset
        On (``structure``, ``record``, ``limit_state``): ``pga_at_limit`` [m s-2],
        ``pgv_at_limit`` [m s-1], ``censored`` (1: a lower bound, -1: not run); per
        record its suite, PGA and PGV.

    Raises
    ------
    InputError
        The file is missing, not NetCDF, or another kind of file.
    """
    return _open(path, "ida")


def open_fragility(path) -> xr.Dataset:
    """Fitted lognormal fragility curves, read into memory.

    Parameters
    ----------
    path : str or os.PathLike
        A file written by :func:`stonedem.fragility.fit.fragility_dataset`, as ``snakemake
        fragility`` writes it.

    Returns
    -------
    xarray.Dataset
        On (``structure``, ``record_set``, ``limit_state``): ``median_pga`` [m s-2] and
        ``beta_pga`` [1] (likewise ``_pgv`` [m s-1]), their bootstrap bands on ``bound``,
        and the curves ``probability_pga`` on ``pga_grid`` [m s-2].

    Raises
    ------
    InputError
        The file is missing, not NetCDF, or another kind of file.
    """
    return _open(path, "fragility")
