"""``stonedem record info FILE``: PGA, duration, dt, predominant frequency and a spectrum plot.

Every argument is checked before the record is read (``--units``, ``--dt``, ``--damping``,
the record's path, then ``--plot`` with :func:`stonedem.entry.check_output_path`: not the
record itself, not a folder, in a writable folder, a .png, .pdf or .svg), the record is
read with the checks of :func:`stonedem.motion.records.read_record` (limits in
:mod:`stonedem.motion.records`), and the plot is written atomically. Bad input raises
:class:`stonedem.errors.InputError` (one line, exit 2 under :func:`stonedem.entry.guarded`).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from stonedem.errors import InputError
from stonedem.io.spec import Field

PLOT_SUFFIXES = (".png", ".pdf", ".svg")
# spectra cost ~20 us per sample and damping (stonedem.motion.records.MAX_RECORD_SAMPLES)
MAX_DAMPINGS = 10
DEFAULT_DAMPING = (0.05, 0.10)
DAMPINGS = Field("--damping", "list", limit=MAX_DAMPINGS, doc="damping ratios of the spectra")
DAMPING = Field("--damping", range="(0, 1)", hint="give damping ratios between 0 and 1, e.g. 0.05")


def add_parser(subparsers) -> None:
    """Add ``stonedem record`` (sub-command ``info``) to a parser's subcommands.

    ``info`` sets ``handler``, a function of the parsed arguments returning the exit
    status (it raises InputError on bad input, which stonedem's main prints and turns into exit 2).
    """
    rec = subparsers.add_parser("record", help="ground-motion records")
    rec_sub = rec.add_subparsers(dest="record_command", required=True)
    info = rec_sub.add_parser(
        "info", help="PGA, duration, dt, predominant frequency; writes a spectrum plot"
    )
    info.add_argument("file", help="record file (.AT2, text, NetCDF) or a name in records/")
    info.add_argument(
        "--units",
        default=None,
        help="acceleration units of a text record: m/s2 (default), g, cm/s2 "
        "(.AT2 and NetCDF records carry their own)",
    )
    info.add_argument(
        "--dt", default=None, metavar="DT", help="time step of a one-column text record [s]"
    )
    info.add_argument(
        "--plot",
        default=None,
        metavar="FILE",
        help="spectrum plot to write, .png, .pdf or .svg "
        "(default results/records/<name>_spectrum.png)",
    )
    info.add_argument(
        "--damping",
        nargs="+",
        default=None,
        metavar="RATIO",
        help=f"damping ratios of the response spectra (default 0.05 0.10; at most {MAX_DAMPINGS})",
    )
    info.set_defaults(handler=command_record_info)


def check_dampings(values) -> list[float]:
    """Damping ratios in (0, 1), at most MAX_DAMPINGS of them, or an InputError naming --damping."""
    if values is None:
        return list(DEFAULT_DAMPING)
    if not values:  # argparse (nargs="+") never gives this; a direct caller may
        raise InputError("--damping", "no value given", "give ratios such as 0.05 0.10")
    return [DAMPING.check(value) for value in DAMPINGS.check(values)]


def command_record_info(args) -> int:
    from stonedem.entry import check_output_path
    from stonedem.io.atomic import write_atomically
    from stonedem.motion import records
    from stonedem.motion.records import RECORD_KEYS, check_units, read_record, resolve_record

    # every argument first, before anything is read or computed
    units = check_units(args.units, "--units")
    dt = RECORD_KEYS["dt"].check(args.dt, "--dt") if args.dt is not None else None
    dampings = check_dampings(args.damping)
    if args.plot is not None and not str(args.plot).strip():
        raise InputError("--plot", "empty path", "give a file name ending in .png")
    path = resolve_record(args.file, "file", Path("."))
    plot = (
        Path(args.plot)
        if args.plot is not None
        else Path("results/records") / f"{path.stem}_spectrum.png"
    )
    plot = check_output_path(plot, "--plot", inputs=[path], suffixes=PLOT_SUFFIXES)

    time, accel, meta = read_record(
        path, "file", units=units, dt=dt, units_field="--units", dt_field="--dt"
    )
    pga = float(np.abs(accel).max())
    f_p = records.predominant_frequency(time, accel)
    _, disp = records.integrate(time, accel)
    shown_path = records.shown(path, 200)
    print(f"record              {shown_path}")
    if meta.get("title"):
        print(f"title               {records.shown(meta['title'], 200)}")
    print(f"PGA                 {pga:.4g} m/s2 ({pga / records.G_STANDARD:.4g} g)")
    print(f"duration            {time[-1]:.4g} s")
    print(f"dt                  {time[1] - time[0]:.4g} s ({len(time)} samples)")
    if math.isnan(f_p):
        # an all-zero or constant record is a valid file whose PGA, spectra (zero) and
        # duration are well defined; only the frequency is not: say so instead of a number
        why = (
            "the record is all zeros"
            if pga == 0
            else "the record is constant"
            if records.is_constant(accel)
            else "no spectral peak in 0.1-25 Hz"
        )
        print(f"predominant freq.   none ({why})")
    else:
        print(f"predominant freq.   {f_p:.3g} Hz (smoothed Fourier amplitude peak)")
    print(
        f"end displacement    {disp[-1]:.4g} m as recorded (baseline correction is applied "
        "when simulating)"
    )
    periods = records.SPECTRUM_PERIODS
    spectra = []
    for z in dampings:
        psa = records.response_spectrum(time, accel, periods, z)
        spectra.append(psa)
        if psa.max() > 0:
            print(
                f"PSA peak ({100 * z:g} %)     {psa.max():.4g} m/s2 at T = "
                f"{periods[np.argmax(psa)]:.3g} s"
            )
        else:
            print(f"PSA peak ({100 * z:g} %)     0 m/s2 (no response)")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 3.8), constrained_layout=True)
    try:
        ax1.plot(time, accel, lw=0.6)
        ax1.set_xlabel("time [s]")
        ax1.set_ylabel("ground acceleration [m s-2]")
        for z, psa in zip(dampings, spectra):
            ax2.plot(periods, psa, label=f"{100 * z:g} % damping")
        ax2.set_xscale("log")
        ax2.set_xlabel("period [s]")
        ax2.set_ylabel("pseudo-acceleration [m s-2]")
        ax2.legend()
        predominant = "none" if math.isnan(f_p) else f"{f_p:.3g} Hz"
        title = records.shown(path.name, 80).replace("$", r"\$")  # no mathtext from a file name
        fig.suptitle(f"{title}: PGA {pga:.3g} m/s2, predominant {predominant}", fontsize=10)
        write_atomically(plot, lambda tmp: fig.savefig(tmp, dpi=110))
    finally:
        plt.close(fig)
    print(f"spectrum plot       {records.shown(plot, 200)}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """A stand-alone ``stonedem``-like parser with only ``record`` (tests; stonedem.cli adds it to
    its own)."""
    parser = argparse.ArgumentParser(prog="stonedem")
    add_parser(parser.add_subparsers(dest="command", required=True))
    return parser
