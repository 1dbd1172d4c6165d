"""Records: AT2 parsing, baseline correction, resampling, spectra and scaling."""

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from stonedem.errors import InputError
from stonedem.motion import records
from stonedem.motion.excitation import excitation_from_spec

AT2_NEW = """PEER NGA STRONG MOTION DATABASE RECORD
Test event 2000, Some Station, 090
ACCELERATION TIME SERIES IN UNITS OF G
NPTS=    7, DT=   .0100 SEC
  .1000000E-01  .2000000E-01 -.1000000E-01  .0000000E+00  .5000000E-01
 -.2500000E-01  .1000000E-01
"""
AT2_OLD = """PACIFIC ENGINEERING AND ANALYSIS STRONG-MOTION DATA
 TEST 01/01/00, STATION, 090
 ACCELERATION TIME HISTORY IN UNITS OF G
   7   0.0100   NPTS, DT
  .1000000E-01  .2000000E-01 -.1000000E-01  .0000000E+00  .5000000E-01
 -.2500000E-01  .1000000E-01
"""


def write(tmp_path, text, name="rec.AT2"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("text", [AT2_NEW, AT2_OLD])
def test_at2_both_header_styles(tmp_path, text):
    rec = records.read_at2(write(tmp_path, text))
    assert rec.dt == pytest.approx(0.01) and len(rec.time) == 7
    assert rec.acceleration[4] == pytest.approx(0.05 * 9.80665, rel=1e-15), "g = 9.80665"


@pytest.mark.parametrize(
    "mutate, message",
    [
        (lambda t: t.replace("NPTS=    7", "NPTS=    8"), "NPTS = 8 but 7 values"),
        (lambda t: t.replace("-.2500000E-01", "    "), "NPTS = 7 but 6 values"),
        (lambda t: t.replace("UNITS OF G", "UNITS OF CM/S/S"), "units of g"),
        (lambda t: t.replace("NPTS=    7, DT=   .0100 SEC", "SEVEN POINTS"), "no NPTS and DT"),
        (lambda t: t.replace(".5000000E-01", "abc"), "non-numeric"),
        (lambda t: "\n".join(t.splitlines()[:3]), "4 header lines"),
    ],
)
def test_malformed_at2_gives_one_line(tmp_path, mutate, message):
    path = write(tmp_path, mutate(AT2_NEW))
    with pytest.raises(InputError) as err:
        excitation_from_spec({"kind": "record", "file": str(path)})
    assert message in str(err.value) and "\n" not in str(err.value), str(err.value)


def test_at2_record_drives_a_scene(tmp_path):
    path = write(tmp_path, AT2_NEW)
    motion = excitation_from_spec({"kind": "record", "file": str(path), "baseline": False})
    assert motion.pga == pytest.approx(0.05 * 9.80665)


def test_baseline_correction_removes_a_known_offset():
    t = np.arange(0, 40.0001, 0.01)
    # a ground motion that starts and ends at rest: d = 0.1 sin(3 pi t) exp(-((t - 10) / 4)^2)
    w = 3 * np.pi
    env = np.exp(-(((t - 10) / 4) ** 2))
    denv = -2 * (t - 10) / 16 * env
    ddenv = (-2 / 16 + (2 * (t - 10) / 16) ** 2) * env
    disp_clean = 0.1 * np.sin(w * t) * env
    clean = 0.1 * (
        -w * w * np.sin(w * t) * env + 2 * w * np.cos(w * t) * denv + np.sin(w * t) * ddenv
    )
    offset = clean + 0.02  # a constant 0.02 m/s2 error: 16 m of drift after 40 s
    _, drift = records.integrate(t, offset)
    corrected = records.baseline_correct(t, offset)
    vel, disp = records.integrate(t, corrected)
    assert abs(drift[-1]) > 15.0
    assert abs(disp[-1]) < 1e-9 and abs(vel[-1]) < 1e-9, "ends at rest"
    error = np.abs(disp - disp_clean).max() / np.abs(disp_clean).max()
    assert error < 0.05, f"the true displacement is recovered to {100 * error:.2f} %, tol 5 %"


def harmonic_sdof_peak(t, amplitude, forcing_w, w, z):
    """Closed-form response from rest of u'' + 2 z w u' + w^2 u = -A sin(W t)."""
    k = w * w - forcing_w**2
    c = 2 * z * w * forcing_w
    # particular C sin + D cos: k C - c D = -A, k D + c C = 0
    C = -amplitude * k / (k * k + c * c)
    D = amplitude * c / (k * k + c * c)
    wd = w * np.sqrt(1 - z * z)
    E = -D
    F = (z * w * E - C * forcing_w) / wd
    u = (
        C * np.sin(forcing_w * t)
        + D * np.cos(forcing_w * t)
        + np.exp(-z * w * t) * (E * np.cos(wd * t) + F * np.sin(wd * t))
    )
    return np.abs(u).max()


@pytest.mark.parametrize("period", [0.1, 0.5, 0.77, 2.0, 4.0])
@pytest.mark.parametrize("damping", [0.05, 0.10])
def test_spectrum_of_a_harmonic_against_the_closed_form(period, damping):
    t = np.arange(0, 30.0, 0.002)
    W = 2 * np.pi * 1.3
    psa = records.response_spectrum(t, 3.0 * np.sin(W * t), [period], damping)[0]
    w = 2 * np.pi / period
    ref = w * w * harmonic_sdof_peak(t, 3.0, W, w, damping)
    assert psa == pytest.approx(ref, rel=2e-3), (
        "exact recurrence vs closed form; the input is sampled"
    )


def test_predominant_frequency_of_a_sine_burst():
    t = np.arange(0, 40, 0.01)
    a = np.sin(2 * np.pi * 2.5 * t) * np.exp(-(((t - 20) / 6) ** 2))
    assert records.predominant_frequency(t, a) == pytest.approx(2.5, rel=0.03)


def test_resampling_does_not_alias():
    t = np.arange(0, 20, 0.001)
    low = np.sin(2 * np.pi * 2 * t)
    high = 0.5 * np.sin(2 * np.pi * 90 * t)  # above the 50 Hz Nyquist of dt = 0.01
    t2, a2 = records.resample(t, low + high, 0.01)
    assert np.abs(a2 - np.sin(2 * np.pi * 2 * t2))[200:-200].max() < 0.02, (
        "90 Hz removed, not folded to 10 Hz"
    )


def test_pga_scaling_is_exact():
    a = np.array([0.1, -0.7, 0.3])
    assert np.abs(records.scale_to_pga(a, 9.81)).max() == 9.81


def test_committed_records_are_self_describing():
    for name in (
        "athens_standin_kocaeli_arc000",
        "kalamata_standin_izmit_izt270",
        "mexico_standin_chichi_tcu102",
        "northridge_1994_mul009",
    ):
        with xr.open_dataset(f"records/{name}.nc") as ds:
            for var in list(ds.data_vars) + list(ds.coords):
                assert ds[var].attrs.get("units") and ds[var].attrs.get("long_name"), (name, var)
            for key in (
                "event",
                "station",
                "component",
                "source",
                "licence",
                "pga",
                "predominant_frequency",
            ):
                assert key in ds.attrs, (name, key)
            assert abs(float(ds.displacement[-1])) < 1e-6


def test_stand_ins_fall_in_the_thesis_frequency_order():
    f = {
        n: xr.open_dataset(f"records/{n}.nc").attrs["predominant_frequency"]
        for n in (
            "athens_standin_kocaeli_arc000",
            "kalamata_standin_izmit_izt270",
            "mexico_standin_chichi_tcu102",
        )
    }
    assert 4.1 <= f["athens_standin_kocaeli_arc000"] <= 8.3
    assert 2.9 <= f["kalamata_standin_izmit_izt270"] <= 3.5
    assert 0.35 <= f["mexico_standin_chichi_tcu102"] <= 0.53


def test_record_info_command(tmp_path):
    plot = tmp_path / "s.png"
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "stonedem",
            "record",
            "info",
            "northridge_1994_mul009",
            "--plot",
            str(plot),
        ],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    assert "PGA                 4.077" in proc.stdout and "predominant" in proc.stdout
    assert plot.stat().st_size > 1000


# --- hostile input (issue 13) -----------------------------------------------------------------


@pytest.mark.parametrize(
    "mutate, message",
    [
        (lambda t: t.replace(".0100", "1e-"), "no NPTS and DT"),
        (lambda t: t.replace(".0100", "."), "no NPTS and DT"),
        (lambda t: t.replace(".0100", "1e999"), "DT = inf s is outside [0.0001, 1] s"),
        (lambda t: t.replace(".0100", "0.0000001"), "outside [0.0001, 1] s"),
        (
            lambda t: t.replace("NPTS=    7", "NPTS= 99999999999999999999"),
            "more than 500000 samples",
        ),
        (lambda t: t.replace("NPTS=    7", "NPTS=    1"), "NPTS = 1"),
        (lambda t: t.replace(".5000000E-01", "nan"), "NaN or infinite value at sample 4"),
        (lambda t: t.replace(".5000000E-01", "1.0E+03"), "above the 100 g limit"),
        (lambda t: t.replace("Test event", "Test\x1b[2J event"), None),
    ],
)
def test_hostile_at2(tmp_path, mutate, message):
    path = write(tmp_path, mutate(AT2_NEW))
    if message is None:  # control characters in the title are escaped, not printed raw
        assert records.read_at2(path).meta["title"].startswith("Test\\x1b[2J event")
        return
    with pytest.raises(InputError) as err:
        excitation_from_spec({"kind": "record", "file": str(path)})
    assert message in str(err.value) and str(err.value).isprintable(), str(err.value)


def test_at2_units_are_its_own(tmp_path):
    path = write(tmp_path, AT2_NEW)
    with pytest.raises(InputError) as err:
        excitation_from_spec({"kind": "record", "file": str(path), "units": "cm/s2"})
    assert err.value.field == "excitation.units" and "in g" in str(err.value)
    assert excitation_from_spec(
        {"kind": "record", "file": str(path), "units": "g", "baseline": False}
    ).pga == pytest.approx(0.05 * 9.80665)


def test_at2_not_utf8_or_binary(tmp_path):
    path = tmp_path / "bad.AT2"
    path.write_bytes(AT2_NEW.encode().replace(b"Some Station", b"Some \xff Station"))
    with pytest.raises(InputError, match=r"line 2: byte \d+ is not UTF-8"):
        records.read_at2(path)
    path.write_bytes(b"\x00" * 100)
    with pytest.raises(InputError, match="binary file"):
        records.read_at2(path)


@pytest.mark.parametrize("accel", [np.zeros(500), np.full(500, 0.7)])
def test_a_constant_record_has_no_predominant_frequency(accel):
    assert np.isnan(records.predominant_frequency(np.arange(500) * 0.01, accel))


def run_info(*argv):
    """(status, stdout, stderr) of ``stonedem record info`` in-process through
    stonedem.motion.cli."""
    import contextlib
    import io

    from stonedem.entry import guarded
    from stonedem.motion.cli import build_parser

    args = build_parser().parse_args(["record", "info", *map(str, argv)])
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = guarded(lambda: args.handler(args))
    return status, out.getvalue(), err.getvalue()


def test_record_info_in_process(tmp_path):
    plot = tmp_path / "s.svg"
    status, out, err = run_info("northridge_1994_mul009", "--plot", plot, "--damping", "0.05")
    assert status == 0, err
    assert "PGA                 4.077" in out and "predominant freq.   1.06 Hz" in out
    assert plot.stat().st_size > 1000 and list(tmp_path.iterdir()) == [plot], "no temporary left"


def test_record_info_of_an_all_zero_record(tmp_path):
    path = tmp_path / "zeros.txt"
    path.write_text("".join(f"{i * 0.01:.2f} 0\n" for i in range(100)))
    status, out, err = run_info(path, "--plot", tmp_path / "z.png")
    assert status == 0, err
    assert (
        "predominant freq.   none (the record is all zeros)" in out
        and "0 m/s2 (no response)" in out
    )


@pytest.mark.parametrize(
    "argv, field",
    [
        (
            ["northridge_1994_mul009", "--units", "g"],
            "error: --units: northridge_1994_mul009.nc: declares",
        ),
        (["northridge_1994_mul009", "--units", "furlong"], "error: --units: unknown units"),
        (["no_such_record", "--damping", "1.5"], "error: --damping: must be > 0 and < 1, got 1.5"),
        (
            ["no_such_record", "--damping", *["0.05"] * 11],
            "error: --damping: 11 items exceed the limit 10",
        ),
        (["no_such_record", "--dt", "abc"], "error: --dt: expected a number"),
        (["no_such_record", "--dt", "nan"], "error: --dt"),
        (
            ["no_such_record", "--dt", "1e-9"],
            "error: --dt: must be >= 0.0001 and <= 1, got 1e-09 s",
        ),
        (["no_such_record"], "error: file: record 'no_such_record' not found"),
        (["northridge_1994_mul009", "--plot", "PLOT/x.txt"], "error: --plot: "),
        (["northridge_1994_mul009", "--plot", "PLOT"], "error: --plot: "),
        (["northridge_1994_mul009", "--plot", ""], "error: --plot: empty path"),
    ],
)
def test_record_info_refuses_before_computing(tmp_path, argv, field):
    argv = [str(tmp_path) if a == "PLOT" else a.replace("PLOT", str(tmp_path)) for a in argv]
    status, out, err = run_info(*argv)
    assert status == 2 and err.startswith(field) and err.count("\n") == 1 and out == "", err
    assert list(tmp_path.iterdir()) == []


def test_record_info_never_overwrites_its_input(tmp_path):
    path = tmp_path / "rec.txt"
    path.write_text("0 0.1\n0.01 0.2\n0.02 -0.1\n")
    path_png = tmp_path / "rec.png"
    path_png.write_bytes(b"x")
    status, out, err = run_info(path_png, "--plot", path_png)
    assert status == 2 and err.startswith("error: --plot: ") and "is the input file" in err, err
    assert path_png.read_bytes() == b"x"
