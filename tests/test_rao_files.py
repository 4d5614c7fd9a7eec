"""RAO readers (ship_motion.rao_files): the same vessel through every door, conventions, bad input.

The files are written here to each format's documented layout (WAMIT's .4, OrcaFlex's
vessel-type text data, our CSV), from one set of RAOs at the CG moved to each format's
reference points and phase conventions by the formulas of the format (written out
below, independently of the reader); the reference-point transfer itself is checked
against rigid-body kinematics in the time domain.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from ship_motion import ClosedFormRao, IrregularSea, Jonswap, RaoTable, motion_from_config
from ship_motion.rao import GRAVITY
from ship_motion.rao_files import SourceFrame, move_to_cg, read_orcaflex, read_wamit_4
from towcable_fmu.common.errors import SceneError
from towcable_fmu.numerics.kinematics import rotation_matrix

OMEGA = np.linspace(0.3, 2.0, 35)
HEADINGS_DEG = np.arange(0.0, 360.0, 15.0)
HALF = HEADINGS_DEG <= 180.0
#: the CG in the source's body axes [m]; the source's RAO origin and phase origin
CG = (-3.2, 0.0, 1.7)
ORIGIN = (4.0, 0.0, -2.5)
PHASE_ORIGIN = (10.0, 0.0)
ULEN = 7.5


def vessel() -> np.ndarray:
    """RAOs at the CG (ours), shape (nf, nh, 6), of a port-starboard symmetric hull: the
    closed-form heave, roll, pitch plus smooth surge, sway (odd in heading) and yaw (odd)."""
    rao = ClosedFormRao()
    out = np.stack([rao(OMEGA, math.radians(h), 0.0) for h in HEADINGS_DEG], axis=1)
    mu = np.radians(HEADINGS_DEG)[None, :]
    k = (OMEGA ** 2 / GRAVITY)[:, None]
    out[..., 0] = 0.6 * np.cos(mu) * np.exp(-2.0 * k) * np.exp(0.4j)
    out[..., 1] = 0.7 * np.sin(mu) * np.exp(-1.5 * k) * np.exp(-0.9j)
    out[..., 5] = 0.02 * k * np.sin(2.0 * mu) * np.exp(1.1j)
    return out


def at_source(values: np.ndarray, origin, phase_origin) -> np.ndarray:
    """RAOs of the source's origin with phases relative to the wave at its phase origin:
    xi_O = xi_G - theta x (r_G - r_O), times exp(-i k (r_G - r_phase) . (cos mu, sin mu))."""
    out = values.copy()
    arm = np.subtract(CG, origin)
    for d, (a, b) in enumerate(((1, 2), (2, 0), (0, 1))):   # (theta x arm)_d = theta_a arm_b - theta_b arm_a
        out[..., d] -= values[..., 3 + a] * arm[b] - values[..., 3 + b] * arm[a]
    mu = np.radians(HEADINGS_DEG)[None, :]
    k = (OMEGA ** 2 / GRAVITY)[:, None]
    shift = (CG[0] - phase_origin[0]) * np.cos(mu) + (CG[1] - phase_origin[1]) * np.sin(mu)
    return out * np.exp(-1j * k * shift)[..., None]


def write_csv(path, values):
    names = [f"{d}_{p}" for d in ("surge", "sway", "heave", "roll", "pitch", "yaw") for p in ("amp", "phase")]
    lines = ["omega,heading," + ",".join(names)]
    for i, w in enumerate(OMEGA):
        for j, h in enumerate(HEADINGS_DEG):
            fields = [repr(float(w)), repr(float(h))]
            for d in range(6):
                v = values[i, j, d] * (180.0 / math.pi if d >= 3 else 1.0)
                fields += [repr(float(abs(v))), repr(float(math.degrees(np.angle(values[i, j, d]))))]
            lines.append(",".join(fields))
    path.write_text("\n".join(lines) + "\n")


def write_wamit(path, values, first_column="period"):
    """WAMIT .4: PER BETA I |Xi| phase Re Im, rotations times ULEN, lead over the wave at the origin."""
    src = at_source(values, (0.0, 0.0, 0.0), (0.0, 0.0))
    lines = []
    for i in np.argsort(-OMEGA):
        x = 2.0 * math.pi / OMEGA[i] if first_column == "period" else OMEGA[i]
        for j in np.flatnonzero(HALF):
            for d in range(6):
                v = src[i, j, d] * (ULEN if d >= 3 else 1.0)
                lines.append(f"{x:.8E} {HEADINGS_DEG[j]:.8E} {d + 1:d} {abs(v):.8E} "
                             f"{math.degrees(np.angle(v)):.8E} {v.real:.8E} {v.imag:.8E}")
    path.write_text("\n".join(lines) + "\n")


def orcaflex_text(values, *, conventions=None, rows_per_direction=None) -> str:
    """An OrcaFlex text data file: one vessel type, one draught, displacement RAOs in degrees,
    phase lags in degrees relative to the crest at the phase origin, periods, half the headings."""
    src = at_source(values, ORIGIN, PHASE_ORIGIN)
    conv = {"WavesReferredToBy": "period (s)", "RAOResponseUnits": "degrees", "RAOWaveUnit": "amplitude",
            "RAOPhaseConvention": "lags", "RAOPhaseUnitsConvention": "degrees",
            "RAOPhaseRelativeToConvention": "crest", "Symmetry": "XZ plane"}
    conv.update(conventions or {})
    head = ", ".join(["RAOPeriodOrFrequency"] + [f"RAO{d}{p}" for d in ("Surge", "Sway", "Heave", "Roll", "Pitch",
                                                                        "Yaw") for p in ("Amp", "Phase")])
    text = ["General:", "  UnitsSystem: SI", "VesselTypes:", "  - Name: Barge", "    Length: 100"]
    text += [f"    {k}: {v}" for k, v in conv.items() if v is not None]
    text += ["    Draughts:", "      - Name: Draught1", f"        CentreOfMass: [{CG[0]!r}, {CG[1]!r}, {CG[2]!r}]",
             "        DisplacementRAOs:", f"          RAOOrigin: [{ORIGIN[0]!r}, {ORIGIN[1]!r}, {ORIGIN[2]!r}]",
             f"          PhaseOrigin: [{PHASE_ORIGIN[0]!r}, {PHASE_ORIGIN[1]!r}, ~]", "          RAOs:"]
    for j in np.flatnonzero(HALF):
        text += [f"            - RAODirection: {float(HEADINGS_DEG[j])!r}", f"              {head}:",
                 "                - [0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0]"]
        for i in np.argsort(-OMEGA)[:rows_per_direction]:
            row = [2.0 * math.pi / OMEGA[i]]
            for d in range(6):
                v = src[i, j, d] * (180.0 / math.pi if d >= 3 else 1.0)
                row += [float(abs(v)), -float(math.degrees(np.angle(v)))]
            text.append("                - [" + ", ".join(repr(float(x)) for x in row) + "]")
    return "\n".join(text) + "\n"


SEA = {"type": "irregular", "hs": 3.0, "tp": 8.0, "heading": 130.0, "speed": 0.0, "components": 80,
       "omega_min": 0.35, "omega_max": 1.9, "seed": 3}


def doors(tmp_path):
    values = vessel()
    write_csv(tmp_path / "rao.csv", values)
    write_wamit(tmp_path / "barge.4", values)
    (tmp_path / "barge.yml").write_text(orcaflex_text(values))
    return {
        "csv": {"file": "rao.csv"},
        "wamit": {"source": "wamit", "file": "barge.4", "ulen": ULEN, "centre_of_gravity": list(CG),
                  "symmetric": True},
        "orcaflex": {"source": "orcaflex", "file": "barge.yml"},
    }


def test_same_vessel_through_every_door_gives_the_same_motion(tmp_path):
    times = np.linspace(0.0, 300.0, 601)
    truth = IrregularSea(Jonswap(3.0, 8.0), RaoTable(OMEGA, np.radians(HEADINGS_DEG), vessel()),
                         heading=math.radians(130.0), components=80, omega_min=0.35, omega_max=1.9, seed=3)
    expected = truth.evaluate_many(times)
    scale = np.abs(expected).max(axis=(0, 1))
    assert np.all(scale > 0.0)
    for name, rao in doors(tmp_path).items():
        got = motion_from_config({**SEA, "rao": rao}, base_dir=tmp_path).evaluate_many(times)
        err = np.abs(got - expected).max(axis=(0, 1)) / scale
        assert err.max() < 2e-7, (name, err)


def test_tables_agree_at_every_heading(tmp_path):
    """All headings of the full circle (the mirrored half included), every frequency."""
    values = vessel()
    write_wamit(tmp_path / "b.4", values, first_column="frequency")
    (tmp_path / "b.yml").write_text(orcaflex_text(values))
    wamit = read_wamit_4(tmp_path / "b.4", ulen=ULEN, centre_of_gravity=CG, first_column="frequency",
                         symmetric=True)
    orca = read_orcaflex(tmp_path / "b.yml")
    for table in (wamit, orca):
        assert table.heading.size - int(table.periodic) == HEADINGS_DEG.size
        np.testing.assert_allclose(table.omega, OMEGA, rtol=1e-12)
        np.testing.assert_allclose(table.values[:, :HEADINGS_DEG.size], values, atol=1e-7 * np.abs(values).max())


HAND_FILE = """\
VesselTypes:
  - Name: Hand
    WavesReferredToBy: frequency (rad/s)
    RAOResponseUnits: degrees
    RAOWaveUnit: amplitude
    RAOPhaseConvention: {convention}
    RAOPhaseUnitsConvention: degrees
    RAOPhaseRelativeToConvention: {event}
    Draughts:
      - Name: D
        CentreOfMass: [5.0, 1.0, 2.0]
        DisplacementRAOs:
          RAOOrigin: [5.0, 1.0, 2.0]
          PhaseOrigin: [~, ~, ~]
          RAOs:
{directions}"""


def hand_file(convention: str, event: str, phase: float) -> str:
    head = ", ".join(["RAOPeriodOrFrequency"] + [f"RAO{d}{p}" for d in ("Surge", "Sway", "Heave", "Roll", "Pitch",
                                                                        "Yaw") for p in ("Amp", "Phase")])
    rows = "".join(f"                - [{w}, 0, 0, 0, 0, 0.8, {phase}, 0, 0, 0, 0, 0, 0]\n" for w in (0.5, 0.9, 1.3))
    directions = "".join(f"            - RAODirection: {d}\n              {head}:\n{rows}" for d in (0, 90, 180, 270))
    return HAND_FILE.format(convention=convention, event=event, directions=directions)


@pytest.mark.parametrize("convention, phase", [("lags", 30.0), ("leads", -30.0)])
@pytest.mark.parametrize("event, event_time", [("crest", 0.0), ("trough", math.pi),
                                               ("zero up-crossing", -0.5 * math.pi)])
def test_regular_wave_phase_against_hand_computation(tmp_path, convention, phase, event, event_time):
    """One wave component a cos(omega t + eps) at the CG; heave 0.8 m/m lagging 30 deg behind the
    wave event (crest at omega t + eps = 0, trough at pi, zero up-crossing at -pi/2), written as a
    lag of 30 or a lead of -30 deg: heave = 0.8 a cos(omega t + eps - event - 30 deg)."""
    path = tmp_path / "hand.yml"
    path.write_text(hand_file(convention, event, phase))
    w = 0.9
    sea = IrregularSea(Jonswap(1.0, 7.0), read_orcaflex(path), heading=math.radians(150.0), components=1,
                       omega_min=w - 0.01, omega_max=w + 0.01, spacing="equal", ramp=0.0)
    a, eps = sea.waves.amplitude[0], sea.waves.phase[0]
    t = np.linspace(0.0, 40.0, 81)
    expected = 0.8 * a * np.cos(w * t + eps - event_time - math.radians(30.0))
    np.testing.assert_allclose(sea.evaluate_many(t)[:, 0, 2], expected, atol=1e-12 * a)
    np.testing.assert_allclose(sea.wave_elevation(t), a * np.cos(w * t + eps), atol=1e-12 * a)
    assert np.all(sea.response[:, [0, 1, 3, 4, 5]] == 0.0)


def test_transfer_to_cg_against_rigid_body_kinematics():
    """A rigid body whose origin P moves by Re(xi_P e^{i w t}) and turns by Re(theta e^{i w t})
    (amplitude 1e-6): the CG's displacement from the rotation matrix, and the RAO moved to the
    CG times the wave elevation there, agree to second order in the amplitude."""
    rng = np.random.default_rng(5)
    w, mu = 0.8, math.radians(35.0)
    k = w * w / GRAVITY
    h_src = rng.normal(size=6) + 1j * rng.normal(size=6)          # per unit wave at the phase origin
    p, o, g = np.array([4.0, -1.0, -2.5]), np.array([10.0, 3.0]), np.array([-3.2, 0.5, 1.7])
    frame = SourceFrame(rao_origin=tuple(p), phase_origin=tuple(o), centre_of_gravity=tuple(g))
    h_cg = move_to_cg([w], [mu], h_src[None, None, :], frame)[0, 0]
    amp = 1e-6
    for t in np.linspace(0.0, 8.0, 17):
        q = (amp * h_src * np.exp(1j * w * t)).real               # the source's motion at time t
        position_cg = p + q[:3] + rotation_matrix(*q[3:]) @ (g - p)
        # the wave elevation at the CG, amp cos(w t - k (r_G - r_O) . (cos mu, sin mu)), as a phasor
        eta_cg = amp * np.exp(1j * (w * t - k * ((g[0] - o[0]) * math.cos(mu) + (g[1] - o[1]) * math.sin(mu))))
        predicted = (h_cg * eta_cg).real
        np.testing.assert_allclose(position_cg - g, predicted[:3], atol=1e3 * amp ** 2)
        np.testing.assert_allclose(q[3:], predicted[3:], atol=1e-18)


def test_mirrored_half_range_needs_symmetric(tmp_path):
    """A half range of headings covers 130 deg only through the mirror image (of 230 deg)."""
    write_wamit(tmp_path / "b.4", vessel())
    table = {**SEA, "heading": 230.0, "rao": {"source": "wamit", "file": "b.4", "ulen": ULEN,
                                              "centre_of_gravity": list(CG)}}
    with pytest.raises(SceneError, match="covering the heading 230") as err:
        motion_from_config(table, base_dir=tmp_path)
    assert err.value.key == "motion.rao.file"
    table["rao"]["symmetric"] = True
    motion_from_config(table, base_dir=tmp_path)


@pytest.mark.parametrize("edit, match", [
    (lambda s: s.replace(" 3 ", " 3 x ", 1), r"line 3 is not numbers"),
    (lambda s: s.replace("\n", " 1.0\n", 1), r"line 1 has 8 fields"),
    (lambda s: s.replace(" 6 ", " 7 ", 1), r"one body, mode I in 1..6; line 6"),
    (lambda s: "\n".join(s.splitlines()[1:]), r"DOF 1 is missing"),
])
def test_malformed_wamit_file_names_the_line(tmp_path, edit, match):
    write_wamit(tmp_path / "b.4", vessel())
    path = tmp_path / "b.4"
    path.write_text(edit(path.read_text()))
    with pytest.raises(SceneError, match=match) as err:
        read_wamit_4(path, ulen=ULEN, centre_of_gravity=CG, key="motion.rao.file")
    assert err.value.key == "motion.rao.file" and "b.4" in str(err.value)


@pytest.mark.parametrize("rao, key", [
    ({"source": "wamit", "file": "b.4", "centre_of_gravity": [0.0, 0.0, 0.0]}, "motion.rao.ulen"),
    ({"source": "wamit", "file": "b.4", "ulen": 1.0}, "motion.rao.centre_of_gravity"),
    ({"source": "wamit", "ulen": 1.0, "centre_of_gravity": [0.0, 0.0, 0.0]}, "motion.rao.file"),
    ({"source": "wamit", "file": "b.4", "ulen": 1.0, "centre_of_gravity": [0.0, 0.0, 0.0], "angle_unit": "deg"},
     "motion.rao.angle_unit"),
    ({"source": "orcaflex", "file": "b.yml", "ulen": 1.0}, "motion.rao.ulen"),
    ({"source": "closed_form", "file": "b.4"}, "motion.rao.file"),
    ({"source": "aqwa", "file": "b.4"}, "motion.rao.source"),
    ({"file": "b.csv", "length": 100.0}, "motion.rao.length"),
    ({"source": "wamit", "file": "b.4", "ulen": 1.0, "centre_of_gravity": [0.0, 0.0, 0.0],
      "first_column": "hertz"}, "motion.rao.first_column"),
])
def test_rao_keys_of_each_source(rao, key, tmp_path):
    with pytest.raises(SceneError) as err:
        motion_from_config({**SEA, "rao": rao}, base_dir=tmp_path)
    assert err.value.key == key


@pytest.mark.parametrize("edit, match", [
    (lambda s: s.replace("    RAOPhaseConvention: lags\n", ""), r"declares RAOPhaseConvention \(one of leads, lags\)"),
    (lambda s: s.replace("RAOResponseUnits: degrees", "RAOResponseUnits: grads"),
     r"RAOResponseUnits one of degrees, radians \(found 'grads'\)"),
    (lambda s: s.replace("UnitsSystem: SI", "UnitsSystem: US"), r"General.UnitsSystem SI"),
    (lambda s: s.replace("Symmetry: XZ plane", "Symmetry: YZ plane"), r"Symmetry one of none, xz plane"),
    (lambda s: s.replace("RAOs:\n", "RAOs:\n  - [\n", 1), r"YAML \(line \d+\)"),
    (lambda s: s.replace(", 1, 0, 0, 0, 0, 0, 0, 0]", ", 1, 0, 0, 0, 0, 0, 0]", 1), r"rows of 13 finite numbers"),
    (lambda s: s.replace("CentreOfMass: [", "CentreOfMass: [1.0, ", 1), r"CentreOfMass a list of 3 numbers"),
])
def test_bad_orcaflex_file_names_the_key(tmp_path, edit, match):
    path = tmp_path / "b.yml"
    path.write_text(edit(orcaflex_text(vessel())))
    with pytest.raises(SceneError, match=match) as err:
        read_orcaflex(path, key="motion.rao.file")
    assert err.value.key == "motion.rao.file" and "b.yml" in str(err.value)


def test_manoeuvre_waves_take_an_rao_file(tmp_path):
    """[motion.waves.rao] of a manoeuvre: the same door, the manoeuvre's speed for the encounter frequency."""
    rao = doors(tmp_path)["wamit"]
    waves = {key: value for key, value in SEA.items() if key != "speed"}
    motion = motion_from_config({"type": "manoeuvre", "speed": 3.0, "waves": {**waves, "rao": rao}},
                                base_dir=tmp_path)
    sea = motion.waves
    assert sea.speed == 3.0 and "barge.4" in sea.rao.description
    alone = motion_from_config({**SEA, "speed": 3.0, "rao": rao}, base_dir=tmp_path)
    np.testing.assert_array_equal(sea.evaluate_many([5.0, 50.0]), alone.evaluate_many([5.0, 50.0]))
