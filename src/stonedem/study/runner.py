"""Run a case (:func:`run_case`: its scene, its run, its dataset) and many cases in one job:
one interpreter start, one compiled-cache load, each record read once
(stonedem.motion.records), one log line per case, and a store of finished cases.

A Snakemake job starts Python, imports xarray and numba, reads its first record and loads
the compiled kernels (1.0-1.5 s) before its first step, so the workflow packs cheap cases into one
job (:func:`stonedem.study.jobs.plan_jobs`) and runs each threshold search in one job. Every grid
case writes its own NetCDF file; a threshold search writes one file, its runs' measures and
histories (:class:`stonedem.study.cube.RunPiece`), not each run's dataset. The *case store*
keeps every finished case (and search file) under a key of its scene, its records' bytes and
the stonedem source, so a job rerun because one of its cases changed re-simulates that case
only and restores the others.

An entry is never the same file as a result: it is a copy, so truncating or editing a case
file cannot reach the store. Each entry is kept with the sha256 of its
bytes (``<key>.sha256``) and checked when it is restored; an entry that fails the check is
moved to ``<store>/corrupt/`` with one warning line (in a read-only store it stays and is
skipped), and the case is simulated again.
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import hashlib
import json
import os
import shutil
import sys
import time as wallclock
from pathlib import Path

import xarray as xr

from stonedem.entry import progress_print
from stonedem.errors import InputError
from stonedem.io.netcdf import write_dataset
from stonedem.motion.suites import record_file_name
from stonedem.study.cube import RunPiece, dataset_piece, run_piece, search_dataset
from stonedem.study.grid import (
    CASE_PARAMETERS,
    REST_AFTER_RECORD,
    Case,
    scene_without_member,
    search_case,
)
from stonedem.study.search import Run, replay, search, search_together, summary

_SOURCE_FINGERPRINT: list[str] = []


def source_fingerprint() -> str:
    """sha256 of the stonedem package's Python sources (a changed kernel invalidates the store)."""
    if not _SOURCE_FINGERPRINT:
        root = Path(__file__).resolve().parents[1]  # the whole package, not this layer
        digest = hashlib.sha256()
        for path in sorted(root.rglob("*.py")):
            digest.update(str(path.relative_to(root)).encode())
            digest.update(path.read_bytes())
        _SOURCE_FINGERPRINT.append(digest.hexdigest())
    return _SOURCE_FINGERPRINT[0]


def _file_digest(path: Path, memo: dict = {}) -> str:  # noqa: B006 - a per-process memo
    stat = path.stat()
    key = (str(path.resolve()), stat.st_size, stat.st_mtime_ns)
    if key not in memo:
        memo[key] = hashlib.sha256(path.read_bytes()).hexdigest()
    return memo[key]


class CaseStore:
    """Finished case files by content key; ``directory`` None: no store (always simulate)."""

    def __init__(self, directory: Path | str | None, records_dir: Path | str = "records"):
        self.directory = Path(directory) if directory else None
        self.records_dir = Path(records_dir)

    def key(self, case: Case) -> str:
        """The case (study, id and scene: a restored file's attributes are its own), the bytes
        of the records it reads and the stonedem sources, hashed."""
        records = []
        excitation = case.scene.get("excitation") or {}
        for spec in (
            excitation,
            excitation.get("vertical") if isinstance(excitation, dict) else None,
        ):
            name = record_file_name(spec)
            if name is not None:
                path = self.records_dir / f"{name}.nc"
                records.append(_file_digest(path) if path.is_file() else name)
        # two studies' identical scenes each keep their own entry: one restored from the other's
        # carried that study's name, case id and title (the SLURM run, whose jobs ran in another
        # order, then differed from the local one in those attributes)
        text = {
            "study": case.study,
            "case": case.id,
            "scene": case.scene,
            "params": case.params,
            "records": records,
            "source": source_fingerprint(),
        }
        if case.search is not None:  # a search system's entry is its whole search file
            text["search"] = dataclasses.asdict(case.search)
        text = json.dumps(text, sort_keys=True, default=repr)
        return hashlib.sha256(text.encode()).hexdigest()[:32]

    def restore(self, case: Case, output: Path, log=None) -> bool:
        """Put a verified copy of the stored file of ``case`` at ``output``; False when there is
        none, or when the entry fails its checksum (then it is moved aside, with one line)."""
        if self.directory is None:
            return False
        stored = self.directory / f"{self.key(case)}.nc"
        if not stored.is_file():
            return False
        output.parent.mkdir(parents=True, exist_ok=True)
        tmp = output.with_name(f".{output.name}.restore")
        try:
            shutil.copyfile(stored, tmp)
        except OSError as err:
            # the copy failed (a full disk, a quota): the entry may well be good, so it stays
            tmp.unlink(missing_ok=True)
            progress_print(
                log or sys.stderr,
                f"warning: case store entry {stored.name} could not be copied "
                f"({err.strerror}); simulating the case again",
            )
            return False
        try:
            good = _sha256(tmp) == _read_checksum(stored)
        except OSError:
            good = False
        if not good:
            tmp.unlink(missing_ok=True)
            self._quarantine(stored, log)
            return False
        os.replace(tmp, output)
        os.utime(output)  # written now, as far as Snakemake's mtime checks are concerned
        return True

    def _quarantine(self, stored: Path, log=None) -> None:
        corrupt = self.directory / "corrupt"
        where = f"moved to {corrupt}"
        try:
            corrupt.mkdir(exist_ok=True)
            for path in (stored, _checksum_path(stored)):
                if path.exists():
                    os.replace(path, corrupt / path.name)
        except OSError:
            try:
                stored.unlink(missing_ok=True)
                where = "removed"
            except OSError as err:
                # a read-only store: the entry stays, and every restore skips it again
                where = f"left in place ({err.strerror}), skipped"
        progress_print(
            log or sys.stderr,
            f"warning: case store entry {stored.name} failed its checksum; "
            f"{where}, simulating the case again",
        )

    def keep(self, case: Case, output: Path) -> None:
        """Remember a finished case file as a copy with its checksum (best effort: a full disk
        only loses the memo)."""
        if self.directory is None:
            return
        stored = self.directory / f"{self.key(case)}.nc"
        tmp = stored.with_name(f".{stored.name}.{os.getpid()}")
        tmp_sum = stored.with_name(f".{stored.stem}.sha256.{os.getpid()}")
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(output, tmp)
            tmp_sum.write_text(_sha256(tmp) + "\n")
            # the checksum first: an entry without its checksum never restores
            os.replace(tmp_sum, _checksum_path(stored))
            os.replace(tmp, stored)
        except OSError:
            for path in (tmp, tmp_sum):
                with contextlib.suppress(OSError):  # a read-only store refuses even this
                    path.unlink(missing_ok=True)


def _checksum_path(stored: Path) -> Path:
    return stored.with_suffix(".sha256")


def _read_checksum(stored: Path) -> str:
    try:
        return _checksum_path(stored).read_text().strip()
    except (OSError, UnicodeDecodeError):
        return ""


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


# a case's log line names the compile of the time loop when it took longer than this [s] (a
# cold cache: ~30 s; a load from the cache: 0.05 s)
COMPILE_SHOWN = 1.0


def run_one(
    case: Case,
    output: Path | str,
    store: CaseStore,
    label: str = "",
    log=None,
    keep_dataset: bool = False,
) -> dict:
    """Simulate ``case`` into ``output`` (or restore it from the store); one log line.

    Returns {collapsed, steps, kernel_seconds, compile_seconds, seconds, restored}, and with
    ``keep_dataset`` ``dataset``: the case dataset written (None when restored: read the file)."""
    output = Path(output)
    start = wallclock.perf_counter()
    restored = store.restore(case, output, log)
    if restored:
        info = _case_info(output)
    else:
        ds = run_case(case, base_dir=store.records_dir)
        write_dataset(ds, output)
        store.keep(case, output)
        info = _info(ds)
    if keep_dataset:
        info["dataset"] = None if restored else ds
    info.update(restored=restored, seconds=wallclock.perf_counter() - start)
    if restored:
        progress_print(
            log or sys.stderr,
            f"{label}{case.study}/{case.id}: restored from the case store; {info['verdict']}",
        )
    # the compile of the time loop (a cold cache's first case), apart from the kernel's stepping
    else:
        progress_print(
            log or sys.stderr,
            run_line(
                label,
                case,
                info["steps"],
                info["kernel_seconds"],
                info["compile_seconds"],
                info["seconds"],
                info["verdict"],
            ),
        )
    return info


def _info(ds) -> dict:
    collapsed = bool(float(ds["collapsed"]) > 0)
    verdict = ds.attrs.get("status", "")
    if collapsed:
        verdict = f"collapsed at {float(ds['collapse_time']):.2f} s ({verdict})"
    return {
        "collapsed": collapsed,
        "steps": int(ds.attrs.get("steps_run", 0)),
        "kernel_seconds": float(ds.attrs.get("wall_seconds", 0.0)),
        "compile_seconds": float(ds.attrs.get("compile_seconds", 0.0)),
        "verdict": verdict,
    }


def _case_info(path: Path) -> dict:
    with xr.open_dataset(path) as ds:
        return _info(ds[["collapsed", "collapse_time"]].load().assign_attrs(ds.attrs))


def run_cases(cases: list[Case], outputs: list, store: CaseStore, log=None) -> list[dict]:
    """Every case into its output file, in order; one log line each."""
    infos = []
    for i, (case, output) in enumerate(zip(cases, outputs)):
        infos.append(run_one(case, output, store, f"[{i + 1}/{len(cases)}] ", log))
    return infos


def run_search(
    system: Case, runs_dir: Path | str | None, summary_path: Path | str, store: CaseStore, log=None
):
    """The threshold search of one system (stonedem.study.search): the runs and the bracket in
    ``summary_path``, one file (restored whole from the store when the search was made before).
    ``runs_dir``: also every run's full case file there (``<case id>.nc``), each kept in the
    store (config ``search_runs: full``); None: none."""
    settings = system.search
    summary_path = Path(summary_path)
    if runs_dir is None and store.restore(system, summary_path, log):
        return restored_search(system, summary_path, log)
    kept: dict[float, Path | xr.Dataset | RunPiece] = {}  # each run's file, dataset or piece
    scenes = SearchScenes(store.records_dir)

    def simulate(value: float, phase: str) -> bool:
        case = search_case(system, value)
        label = f"[{settings.parameter} run {len(kept) + 1}, {phase}] "
        if runs_dir is None:
            kept[value] = run_slim(case, store.records_dir, label, log, scenes, settings.histories)
            return kept[value].collapsed
        path = Path(runs_dir) / f"{case.id}.nc"
        info = run_one(case, path, store, label, log, keep_dataset=True)
        kept[value] = path if info["dataset"] is None else info["dataset"]
        return info["collapsed"]

    runs: list[Run] = search(simulate, settings)
    result = summary(runs, settings)
    progress_print(log or sys.stderr, search_line(system, result))
    write_dataset(search_dataset(system, runs, [kept[r.value] for r in runs], result), summary_path)
    if runs_dir is None:
        store.keep(system, summary_path)
    return runs, result


def restored_search(system: Case, path: Path | str, log=None) -> tuple[list[Run], dict]:
    """The runs (in the order the search made them) and summary of a search file restored from
    the store; its log line."""
    with xr.open_dataset(path) as ds:
        runs = [
            Run(float(v), bool(c), str(p))
            for _, v, c, p in sorted(
                zip(
                    ds["search_order"].values,
                    ds[system.search.parameter].values,
                    ds["collapsed"].values,
                    ds["search_phase"].values,
                )
            )
        ]
    result = summary(runs, system.search)
    progress_print(
        log or sys.stderr, f"{search_line(system, result)} (restored from the case store)"
    )
    return runs, result


def run_slim(
    case: Case,
    records_dir: Path | str,
    label: str = "",
    log=None,
    scenes: SearchScenes | None = None,
    histories: bool = True,
) -> RunPiece:
    """Simulate ``case`` and keep what its search keeps (:class:`stonedem.study.cube.RunPiece`):
    no dataset, no file; one log line, as :func:`run_one` gives. ``scenes``: its search's
    scenes (built from the search's first), else the case's scene is built in full;
    ``histories`` False: the measures alone (its search keeps no histories)."""
    from stonedem.engine.run import checked_run

    start = wallclock.perf_counter()
    run = checked_run(scenes(case) if scenes is not None else case_scene(case, records_dir))
    piece = run_piece(case, run, histories)
    status = run.checks["status"]
    verdict = (
        f"collapsed at {run.result.collapse_time:.2f} s ({status})" if piece.collapsed else status
    )
    progress_print(
        log or sys.stderr,
        run_line(
            label,
            case,
            run.result.steps_run,
            run.result.wall_seconds,
            run.compile_seconds,
            wallclock.perf_counter() - start,
            verdict,
        ),
    )
    return piece


def run_line(
    label: str,
    case: Case,
    steps: int,
    kernel: float,
    compile_seconds: float,
    seconds: float,
    verdict: str,
) -> str:
    """A run's log line: its steps, kernel and compile time (above COMPILE_SHOWN), and verdict."""
    compiled = f"{compile_seconds:.1f} s compile, " if compile_seconds > COMPILE_SHOWN else ""
    return (
        f"{label}{case.study}/{case.id}: {steps} steps, {kernel:.2f} s kernel, "
        f"{compiled}{seconds:.2f} s in all; "
        f"{verdict}"
    )


def search_line(system: Case, result: dict) -> str:
    """The log line of a finished search: how it ended, its bracket, runs and resurrections."""
    return (
        f"{system.study}/{system.id}: {result['status']}, {system.search.parameter} "
        f"{result['lower']:.4g} ... {result['upper']:.4g} (width {result['width']:.2%}), "
        f"{result['n_runs']} runs, resurrections: {result['resurrections'] or 'none'}"
    )


# runs per search and round of run_searches (stonedem.study.search.search_together): 16 gives
# 3 rounds for a 14-run search, 48 runs simulated
SEARCH_WIDTH = 16


def run_searches(
    systems: list[Case],
    runs_dirs: list | None,
    summary_paths: list,
    store: CaseStore,
    device: str = "cpu",
    width: int = SEARCH_WIDTH,
    log=None,
) -> list[tuple[list[Run], dict]]:
    """The threshold searches of ``systems`` together, in rounds
    (:func:`stonedem.study.search.search_together`): each round's runs restored from the store
    where they are, the others simulated side by side on ``device``
    (:func:`stonedem.study.runner.run_cases_together`). Each search's runs, run files and
    summary are those :func:`run_search` gives: a run is written (and kept in the store) once
    it is on the search's path; the speculative runs off it are dropped. The summary's attrs
    say the device and the plan. ``runs_dirs`` None: no run files, and each search file kept
    in (and restored whole from) the store, as :func:`run_search` without a ``runs_dir``."""
    log = log or sys.stderr
    if runs_dirs is None:  # searches made before come back whole; the others run together
        done: dict[int, tuple[list[Run], dict]] = {}
        for i, (system, path) in enumerate(zip(systems, summary_paths)):
            if store.restore(system, Path(path), log):
                done[i] = restored_search(system, path, log)
        todo = [i for i in range(len(systems)) if i not in done]
        if todo:
            ran = _searches_together(
                [systems[i] for i in todo],
                None,
                [summary_paths[i] for i in todo],
                store,
                device,
                width,
                log,
            )
            done.update(zip(todo, ran))
        return [done[i] for i in range(len(systems))]
    return _searches_together(systems, runs_dirs, summary_paths, store, device, width, log)


def _searches_together(systems, runs_dirs, summary_paths, store, device, width, log):
    settings = [system.search for system in systems]
    known: list[dict[float, bool]] = [
        {} for _ in systems
    ]  # value -> collapsed, as search_together has it
    # the files of the runs kept (on the path, or restored from the store); the summaries read
    # them back: every search's datasets held at once could outgrow the memory of a job. Without
    # run files, the runs' pieces
    files: list[dict[float, Path | RunPiece]] = [{} for _ in systems]
    simulated = [0]

    def output(i: int, value: float) -> tuple[Case, Path | None]:
        case = search_case(systems[i], value)
        return case, None if runs_dirs is None else Path(runs_dirs[i]) / f"{case.id}.nc"

    def simulate(items: list[tuple[int, float]]) -> list[xr.Dataset]:
        simulated[0] += len(items)
        return run_cases_together(
            [output(i, value)[0] for i, value in items], store.records_dir, device
        )

    def write(i: int, value: float, ds: xr.Dataset) -> None:
        case, path = output(i, value)
        if path is None:
            files[i][value] = dataset_piece(ds)
            return
        write_dataset(ds, path)
        store.keep(case, path)
        files[i][value] = path

    def run_many(requests):
        start = wallclock.perf_counter()
        collapsed: list[bool | None] = [None] * len(requests)
        todo = []
        for k, (i, value, _) in enumerate(requests):
            case, path = output(i, value)
            if path is not None and store.restore(case, path, log):
                files[i][value] = path
                collapsed[k] = _case_info(path)["collapsed"]
            else:
                todo.append(k)
        pending: dict[tuple[int, float], xr.Dataset] = {}
        for k, ds in zip(todo, simulate([requests[k][:2] for k in todo])):
            collapsed[k] = _info(ds)["collapsed"]
            pending[requests[k][:2]] = ds
        for (i, value, _), c in zip(requests, collapsed):
            known[i][value] = c
        for i in {i for i, _, _ in requests}:  # runs now on the path are final: write them
            for run in replay(known[i], settings[i])[0]:
                if (i, run.value) in pending:
                    write(i, run.value, pending[(i, run.value)])
        progress_print(
            log,
            f"round of {len(requests)} runs over {len({i for i, _, _ in requests})} searches: "
            f"{len(todo)} simulated on the {device.upper()}, {len(requests) - len(todo)} restored, "
            f"{wallclock.perf_counter() - start:.1f} s",
        )
        return collapsed

    all_runs, rounds = search_together(run_many, settings, width)
    # a run dropped as speculative that the path reached later, through another branch: again
    late = [
        (i, r.value) for i, runs in enumerate(all_runs) for r in runs if r.value not in files[i]
    ]
    for (i, value), ds in zip(late, simulate(late)):
        if _info(ds)["collapsed"] != known[i][value]:
            raise RuntimeError(
                f"{systems[i].study}/{output(i, value)[0].id}: simulated again, its collapse "
                f"verdict changed; the device does not repeat runs bit for bit"
            )
        write(i, value, ds)
    for i, runs in enumerate(all_runs):  # files restored from the store off the path
        on_path = {r.value for r in runs}
        for value in [v for v in files[i] if v not in on_path]:
            kept = files[i].pop(value)
            if isinstance(kept, Path):
                kept.unlink(missing_ok=True)
    plan = (
        f"search_together: rounds of up to {width} runs per search (stonedem.study.search); "
        f"{rounds} rounds, {simulated[0]} runs simulated for {sum(map(len, all_runs))} kept"
    )
    out = []
    for system, runs, written, summary_path in zip(systems, all_runs, files, summary_paths):
        result = summary(runs, system.search)
        progress_print(log, search_line(system, result))
        ds = search_dataset(system, runs, [written[r.value] for r in runs], result)
        ds.attrs.update(device=device, search_plan=plan, **library_versions())
        write_dataset(ds, summary_path)
        if runs_dirs is None:
            store.keep(system, Path(summary_path))
        out.append((runs, result))
    return out


def choose_device(wanted: str) -> tuple[str, str]:
    """(device to run on, one line saying which and why): the GPU when one can run the loop,
    else the CPU ensemble on every core."""
    if wanted != "gpu":
        return "cpu", "device: cpu"
    from stonedem.kernels.gpu import gpu_available

    usable, why = gpu_available()
    if usable:
        return "gpu", f"device: gpu ({why})"
    return (
        "cpu",
        f"device: gpu asked for, but {why}: running the searches together on the CPU's cores "
        "instead",
    )


def machine() -> str:
    """The platform and CPU model (results of chaotic runs depend on the CPU's arithmetic)."""
    import platform

    model = platform.processor() or platform.machine()
    with contextlib.suppress(OSError):
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    return f"{platform.platform()}, {model}, {os.cpu_count()} cores"


def library_versions() -> dict[str, str]:
    """Versions of the libraries that computed a result (numba-cuda: 'not installed' without it)."""
    from importlib.metadata import PackageNotFoundError, version

    import numba
    import numpy as np

    try:
        cuda = version("numba-cuda")
    except PackageNotFoundError:
        cuda = "not installed"
    return {
        "numba_version": numba.__version__,
        "numpy_version": np.__version__,
        "numba_cuda_version": cuda,
    }


# --- one case: its scene, its run and its dataset (moved from stonedem.study.grid) ----------


def run_case(case: Case, base_dir: Path | str = ".") -> xr.Dataset:
    """Simulate one case: the scene's dataset with the swept parameters as scalar coordinates."""
    from stonedem.engine.run import run_scene

    return case_dataset(case, run_scene(case_scene(case, base_dir)))


def run_cases_together(
    cases: list[Case], base_dir: Path | str = ".", device: str = "cpu"
) -> list[xr.Dataset]:
    """:func:`run_case` of each case, simulated side by side on ``device``
    (:func:`stonedem.engine.run.run_scenes`; on the GPU the cases must share a structure)."""
    from stonedem.engine.run import run_scenes

    scenes = [case_scene(case, base_dir) for case in cases]
    return [case_dataset(case, ds) for case, ds in zip(cases, run_scenes(scenes, device=device))]


def case_scene(case: Case, base_dir: Path | str = "."):
    """The case's Scene; a record's own length (plus the rest after it) when it gives no
    duration."""
    from stonedem.engine.scene import scene_from_dict
    from stonedem.study.members import member_scene

    scene_spec, member = scene_without_member(copy.deepcopy(case.scene))
    solver = scene_spec.setdefault("solver", {})
    if solver.get("duration") is None:
        solver["duration"] = natural_duration(scene_spec.get("excitation"), base_dir)
    scene = scene_from_dict(scene_spec, base_dir=base_dir)
    return (
        scene if member is None else member_scene(scene, member["member"], member["perturbation"])
    )


class SearchScenes:
    """The Scenes of one threshold search's runs, each what :func:`case_scene` gives: the first
    built in full, every later one from it with only its base motion built anew
    (:func:`stonedem.engine.scene.scene_with_excitation`), since a search sweeps an excitation
    parameter alone (SEARCH_PARAMETERS) and keeps the member. The runs then share the first's
    bodies, which lets each plan reuse what depends on the bodies alone."""

    def __init__(self, base_dir: Path | str = "."):
        self.base_dir = base_dir
        self.first = None

    def __call__(self, case: Case):
        from stonedem.engine.scene import scene_with_excitation

        if self.first is None:
            self.first = case_scene(case, self.base_dir)
            return self.first
        return scene_with_excitation(self.first, scene_without_member(case.scene)[0], self.base_dir)


def case_dataset(case: Case, ds: xr.Dataset) -> xr.Dataset:
    """A scene's dataset as the case's: its swept parameters as scalar coordinates."""
    for key, value in case.params.items():
        _, units, long_name, _ = CASE_PARAMETERS[key]
        ds = ds.assign_coords(
            {key: xr.Variable((), value, {"units": units, "long_name": long_name})}
        )
    ds.attrs.update(study=case.study, case=case.id)
    if "ensemble" in case.scene:
        ds.attrs["ensemble_perturbation"] = case.scene["ensemble"]["perturbation"]
    return ds


def natural_duration(excitation: dict | None, base_dir) -> float:
    """A record's own length, plus REST_AFTER_RECORD for the structure to come to rest, when
    a case gives no duration."""
    from stonedem.motion.excitation import excitation_pair

    # a search's runs differ only in the scale, which leaves the length as it is
    key = json.dumps(
        [{k: v for k, v in (excitation or {}).items() if k not in ("pga", "scale")}, str(base_dir)],
        sort_keys=True,
        default=repr,
    )
    if key not in _DURATIONS:
        horizontal, _ = excitation_pair(excitation, Path(base_dir))
        if horizontal.duration is None:
            raise InputError(
                "solver.duration",
                "missing and the excitation has no natural length",
                "give solver: {duration: ...} in the study",
            )
        if len(_DURATIONS) >= 64:
            _DURATIONS.clear()
        _DURATIONS[key] = horizontal.duration
    return _DURATIONS[key] + REST_AFTER_RECORD


_DURATIONS: dict = {}  # natural_duration's excitations' lengths [s] in this process
