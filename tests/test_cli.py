"""The command line: static summary as JSON, runs to CSV, overrides, errors."""

from __future__ import annotations

import csv
import json
import subprocess
import sys

import pytest

from towcable_fmu import contract
from towcable_fmu.cli import main

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


def test_console_script_is_installed():
    proc = subprocess.run([sys.executable, "-m", "towcable_fmu.cli", "scenes"], capture_output=True, text=True,
                          check=True)
    assert "hanging_cable" in proc.stdout
