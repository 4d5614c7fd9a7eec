"""The command line: static summary as JSON, runs to CSV, overrides, errors (naming the key,
the value and the allowed range), and the progress line of long runs."""

from __future__ import annotations

import csv
import io
import json
import re
import subprocess
import sys

import pytest

from towcable_fmu.common import contract
from towcable_fmu import cli
from towcable_fmu.cli import main
from towcable_fmu.common.run_io import Progress

G = 9.81


def test_static_json_reports_contract_names_and_correct_tension(capsys):
    assert main(["static", "hanging_cable", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    expected_top = (450 * 0.389 + 250) * G
    assert data["tension.top"] == pytest.approx(expected_top, rel=1e-6)
    assert data["tension.towbody"] == pytest.approx(250 * G, rel=1e-6)
    assert data["angle.top"] == pytest.approx(0.0, abs=1e-6)
    assert data["towbody.z"] < -450.0
    assert data["solver.statics_iterations"] > 0
    for key in data:
        contract.unit_of(key)  # every key has a unit in the contract


def test_set_override_changes_the_scene(capsys):
    assert main(["static", "hanging_cable", "--json", "--set", "towbody.mass=100",
                 "--set", "cable.segments[0].elements=20"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["tension.top"] == pytest.approx((450 * 0.389 + 100) * G, rel=1e-6)


def test_run_writes_csv_with_contract_columns_and_plot(tmp_path):
    out = tmp_path / "run.csv"
    png = tmp_path / "run.png"
    assert main(["run", "hanging_cable", "--duration", "1.0", "--output", str(out), "--plot", str(png),
                 "--interval", "0.1", "--quiet"]) == 0
    with open(out) as fh:
        rows = list(csv.reader(fh))
    header = rows[0]
    assert header[0] == "time" and "tension.top" in header and "towbody.z" in header
    assert len(rows) == 1 + 11
    assert float(rows[-1][0]) == pytest.approx(1.0)
    assert png.stat().st_size > 10_000


@pytest.mark.parametrize("args,fragment", [
    (["static", "no_such_scene"], "no_such_scene"),
    (["static", "hanging_cable", "--set", "cable.segments[0].length=-3"], "cable.segments[0].length"),
    (["static", "hanging_cable", "--set", "cable.segments[0].elements=0"], "cable.segments[0].elements"),
    (["static", "hanging_cable", "--set", "cable.segments[0].EA=nan"], "cable.segments[0].EA"),
    (["static", "hanging_cable", "--set", "solver.tim_step=0.1"], "did you mean 'time_step'"),
    (["static", "hanging_cable", "--set", "cable.segments[3].length=1"], "cable.segments[3]"),
])
def test_bad_input_gives_clear_error_naming_the_key(capsys, args, fragment):
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "error" in err and fragment in err


# (override, key, value as given, allowed range as documented in docs/reference/scene_keys.md)
BAD_VALUES = [
    ("cable.segments[0].length=-3", "cable.segments[0].length", "-3", "> 0 [m]"),
    ("cable.segments[0].elements=0", "cable.segments[0].elements", "0", ">= 1 and <= 5000"),
    ("cable.segments[0].elements=6000", "cable.segments[0].elements", "6000", ">= 1 and <= 5000"),
    ("cable.segments[0].EA=nan", "cable.segments[0].EA", "nan", "> 0 [N]"),
    ("cable.segments[0].mass_per_length=0.0", "cable.segments[0].mass_per_length", "0.0", "> 0 [kg/m]"),
    ("solver.time_step=0", "solver.time_step", "0", "> 0 and <= 10 [s]"),
    ("towbody.mass=-5", "towbody.mass", "-5", "> 0 [kg]"),
    ("cable.segments[0].loading='round'", "cable.segments[0].loading", "'round'",
     "one of 'bare', 'faired', 'sun2011_bare', 'sun2011_faired'"),
]


@pytest.mark.parametrize("override,key,value,allowed", BAD_VALUES, ids=[b[0] for b in BAD_VALUES])
def test_bad_value_message_names_key_value_and_allowed_range(capsys, override, key, value, allowed):
    """docs/design.md ("Design rules"): out-of-range values are errors that name the key,
    the value and the allowed range, e.g. ``cable.segments[0].length = -3 ... > 0 [m]``, in
    that order."""
    assert main(["static", "hanging_cable", "--set", override]) == 2
    captured = capsys.readouterr()
    err = captured.err
    assert captured.out == ""  # nothing solved, nothing printed
    assert "error" in err
    assert re.search(re.escape(key) + r"\s*=\s*" + re.escape(value) + r"(?![\w.]).*" + re.escape(allowed), err), err
    assert "Traceback" not in err


def test_bad_value_in_a_scene_file_names_key_value_and_allowed_range(tmp_path, capsys):
    """The same message for a user's TOML file (not only for --set)."""
    from importlib import resources

    text = (resources.files("towcable_fmu") / "builtin_scenes" / "hanging_cable.toml").read_text(encoding="utf-8")
    assert "mass = 250.0" in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("mass = 250.0", "mass = -250.0"))
    assert main(["static", str(bad)]) == 2
    err = capsys.readouterr().err
    assert re.search(r"towbody\.mass\s*=\s*-250\.0(?![\w.]).*" + re.escape("> 0 [kg]"), err), err


class _Clock:
    """A settable stand-in for time.perf_counter."""

    def __init__(self):
        self.now = 1000.0

    def __call__(self):
        return self.now


@pytest.fixture
def clock(monkeypatch):
    c = _Clock()
    monkeypatch.setattr(cli.time, "perf_counter", c)
    return c


def _numbers(line):
    """t, t_end, percent, real-time factor and ETA parsed from one progress line."""
    m = re.fullmatch(r"\s*t =\s*([-\d.]+) / ([-\d.]+) s\s+\(\s*([-\d.]+) %\)\s+([-\d.]+) x real time"
                     r"\s+ETA\s+([-\d.]+) s\s*", line)
    assert m, repr(line)
    return tuple(float(g) for g in m.groups())


def test_progress_prints_time_percent_real_time_factor_eta_and_final_newline(clock):
    """Simulated run from t = 10 s to 70 s; the wall clock advances 2 s per 10 s simulated:
    5x real time. At t = 30: 33.3 % done, ETA 40 s / 5 = 8 s. At the end: 100 %, ETA 0,
    and the line is closed with a newline."""
    out = io.StringIO()
    progress = Progress(every=0.0, stream=out)
    progress(10.0, 70.0)  # the first call fixes the start of the simulated span
    clock.now += 4.0
    progress(30.0, 70.0)
    clock.now += 8.0
    progress(70.0, 70.0)
    text = out.getvalue()
    assert text.endswith("\n") and text.count("\n") == 1
    lines = [seg for seg in text.rstrip("\n").split("\r") if seg]
    t, t_end, pct, rate, eta = _numbers(lines[-2])
    assert (t, t_end) == (30.0, 70.0)
    assert pct == pytest.approx(100.0 * 20.0 / 60.0, abs=0.05)
    assert rate == pytest.approx(20.0 / 4.0, abs=0.05)
    assert eta == pytest.approx(40.0 / 5.0, abs=0.05)
    t, t_end, pct, rate, eta = _numbers(lines[-1])
    assert (t, t_end, pct) == (70.0, 70.0, 100.0)
    assert rate == pytest.approx(60.0 / 12.0, abs=0.05)
    assert eta == pytest.approx(0.0, abs=0.05)
    # each line starts with a carriage return, so it overwrites the previous one
    assert text.startswith("\r") and text.count("\r") == len(lines)


def test_progress_is_silent_for_a_run_shorter_than_every(clock):
    out = io.StringIO()
    progress = Progress(every=2.0, stream=out)
    for k in range(11):
        clock.now += 0.15  # 1.65 s of wall time in all, below every = 2 s
        progress(0.1 * k, 1.0)
    assert out.getvalue() == ""


def test_progress_prints_at_most_every_interval_then_the_end(clock):
    """every = 2 s: over 7 s of wall time in 0.5 s ticks, lines at 2, 4, 6 s and at the end."""
    out = io.StringIO()
    progress = Progress(every=2.0, stream=out)
    n = 14
    for k in range(n + 1):
        progress(float(k), float(n))
        clock.now += 0.5
    text = out.getvalue()
    lines = [seg for seg in text.rstrip("\n").split("\r") if seg]
    times = [_numbers(line)[0] for line in lines]
    assert times == [4.0, 8.0, 12.0, 14.0]
    assert text.endswith("\n")


def test_progress_rate_counts_from_the_first_report_not_from_the_set_up(clock):
    """100 s of set-up (the kernels compiling) before the run's first report at t = 0;
    then 30 s simulated in 6 s of wall time: 5x real time, not 30 / 106."""
    out = io.StringIO()
    progress = Progress(every=2.0, stream=out)
    clock.now += 100.0
    progress(0.0, 60.0)
    clock.now += 6.0
    progress(30.0, 60.0)
    t, t_end, pct, rate, eta = _numbers(out.getvalue().strip("\r"))
    assert (t, pct) == (30.0, 50.0)
    assert rate == pytest.approx(5.0, abs=0.05)
    assert eta == pytest.approx(6.0, abs=0.05)


def test_progress_of_an_empty_run_after_a_long_set_up_prints_nothing(clock):
    """A run of no simulated time whose only report is its end (a 1 s run that took one
    block), after a set-up longer than ``every``: no division by the empty span."""
    out = io.StringIO()
    progress = Progress(every=2.0, stream=out)
    clock.now += 100.0
    progress(10.0, 10.0)
    assert out.getvalue() == ""


def test_console_script_is_installed():
    proc = subprocess.run([sys.executable, "-m", "towcable_fmu.cli", "scenes"], capture_output=True, text=True,
                          check=True)
    assert "hanging_cable" in proc.stdout


def test_static_contact_plot_is_written_for_a_scene_with_a_pulley(tmp_path, capsys):
    png = tmp_path / "contact.png"
    assert main(["static", "pulley_static", "--contact-plot", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000


def test_static_contact_plot_refuses_a_scene_without_contact(tmp_path, capsys):
    png = tmp_path / "contact.png"
    assert main(["static", "hanging_cable", "--contact-plot", str(png)]) == 2
    assert "no winch drum or sheave" in capsys.readouterr().err and not png.exists()
