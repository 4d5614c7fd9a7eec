"""Calnan's enclosing ellipsoid (closed forms for Gaussian and uniform clouds) and the
heave-compensation study (files written, physically consistent statistics)."""

from __future__ import annotations

import csv
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from scipy.stats import chi2

import towcable_fmu
from towcable_fmu.analysis import Ellipsoid, enclosing_ellipsoid, projected_outline
from towcable_fmu.common.errors import SceneError

CENTRE = np.array([-469.5, 0.3, -102.8])  # m, far from the origin like a towed-body track


def rotation(seed: int) -> np.ndarray:
    """A random rotation matrix (columns: the rotated x, y, z axes)."""
    return Rotation.random(random_state=seed).as_matrix()


def inside_share(ell: Ellipsoid, points: np.ndarray) -> float:
    """Share of ``points`` inside ``ell``, computed here from its centre, axes and radii."""
    local = (points - ell.centre) @ ell.axes.T
    return float(np.mean(np.sum((local / ell.radii) ** 2, axis=1) <= 1.0 + 1e-12))


def unit_sphere(rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` points uniformly distributed on the unit sphere."""
    v = rng.standard_normal((n, 3))
    return v / np.linalg.norm(v, axis=1)[:, None]


# ---------------------------------------------------------------------------- the ellipsoid
def test_gaussian_cloud_gives_its_95_percent_confidence_ellipsoid():
    """Normal positions with covariance R diag(s^2) R^T: the axes are R's columns, the radii
    s_i sqrt(chi2_3(0.95)) (the squared Mahalanobis distance is chi-squared with 3 degrees of
    freedom), and a fresh sample of the same distribution is 95 % inside.

    Tolerances: n = 40 000 gives standard deviations within 0.4 %, axis directions within
    about 0.15 deg, the quantile within 0.4 %, the fresh share within 0.2 % (binomial)."""
    rng = np.random.default_rng(7)
    rot = rotation(3)
    sigma = np.array([4.0, 1.5, 0.3])
    n = 40_000
    sample = lambda: CENTRE + (rng.standard_normal((n, 3)) * sigma) @ rot.T  # noqa: E731
    ell = enclosing_ellipsoid(sample())

    assert ell.centre == pytest.approx(CENTRE, abs=5 * sigma.max() / math.sqrt(n))
    np.testing.assert_allclose(ell.axes @ ell.axes.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(ell.axes) == pytest.approx(1.0)
    for i in range(3):
        assert abs(ell.axes[i] @ rot[:, i]) > math.cos(math.radians(1.0)), f"axis {i}"
    np.testing.assert_allclose(ell.radii / ell.radii[0], sigma / sigma[0], rtol=0.02)
    np.testing.assert_allclose(ell.radii, sigma * math.sqrt(chi2.ppf(0.95, 3)), rtol=0.02)
    assert ell.volume == pytest.approx(4.0 / 3.0 * math.pi * np.prod(ell.radii), rel=1e-12)
    assert 0.95 <= ell.fraction_inside <= 0.95 + 1e-3
    assert inside_share(ell, sample()) == pytest.approx(0.95, abs=0.008)


def test_other_fraction_follows_chi_squared():
    """At fraction 0.5 the scale is sqrt(chi2_3(0.5)) (1.54), not the 95 % one."""
    rng = np.random.default_rng(11)
    sigma = np.array([2.0, 1.0, 0.5])
    ell = enclosing_ellipsoid(rng.standard_normal((40_000, 3)) * sigma, fraction=0.5)
    np.testing.assert_allclose(ell.radii, sigma * math.sqrt(chi2.ppf(0.5, 3)), rtol=0.02)
    assert ell.fraction_inside == pytest.approx(0.5, abs=1e-3)


def test_interior_plus_outliers_on_a_larger_surface_recovers_the_ellipsoid():
    """95 % of the points fill a known ellipsoid (a, b, c) uniformly, 5 % lie on the surface of
    the same ellipsoid scaled by 2. Both parts have the shape (a, b, c), so the fit must return
    that ellipsoid: its 95 % contains exactly the interior points. Tolerance 3 % on the radii:
    the shape comes from the standard deviations (about 1 % each at n = 20 000) and the scale
    from the most distant interior point (within 1e-4 of the surface)."""
    rng = np.random.default_rng(5)
    rot = rotation(8)
    radii = np.array([3.0, 2.0, 0.5])
    n_in, n_out = 19_000, 1_000
    interior = unit_sphere(rng, n_in) * rng.random(n_in)[:, None] ** (1.0 / 3.0)
    outliers = 2.0 * unit_sphere(rng, n_out)
    points = CENTRE + (np.vstack([interior, outliers]) * radii) @ rot.T
    ell = enclosing_ellipsoid(rng.permutation(points))
    np.testing.assert_allclose(ell.radii, radii, rtol=0.03)
    for i in range(3):
        assert abs(ell.axes[i] @ rot[:, i]) > math.cos(math.radians(2.0)), f"axis {i}"
    assert ell.volume == pytest.approx(4.0 / 3.0 * math.pi * np.prod(radii), rel=0.06)
    assert ell.fraction_inside == pytest.approx(0.95, abs=1e-12)
    assert inside_share(ell, CENTRE + (interior * radii) @ rot.T) > 0.99


def test_fraction_one_on_a_surface_gives_that_surface():
    """All points on the surface of (a, b, c) and fraction 1: every point inside, the radii
    those of the surface (the standard deviations are a, b, c / sqrt(3) within about 1 %)."""
    rng = np.random.default_rng(2)
    radii = np.array([1.2, 0.8, 0.1])
    rot = rotation(4)
    points = CENTRE + (unit_sphere(rng, 20_000) * radii) @ rot.T
    ell = enclosing_ellipsoid(points, fraction=1.0)
    assert ell.fraction_inside == 1.0
    np.testing.assert_allclose(ell.radii, radii, rtol=0.03)


def test_planar_and_collinear_clouds_give_zero_volume_not_nan():
    rng = np.random.default_rng(3)
    uv = rng.standard_normal((500, 2)) * [2.0, 0.5]
    e1, e2 = np.array([1.0, 0.0, 0.3]) / math.hypot(1.0, 0.3), np.array([0.0, 1.0, 0.0])
    plane = CENTRE + uv[:, :1] * e1 + uv[:, 1:] * e2
    ell = enclosing_ellipsoid(plane)
    assert np.all(np.isfinite(ell.radii)) and np.all(np.isfinite(ell.axes))
    assert ell.volume == 0.0 and ell.radii[2] == 0.0 and ell.radii[1] > 0.0
    assert abs(ell.axes[2] @ np.cross(e1, e2)) == pytest.approx(1.0, abs=1e-9)
    assert ell.fraction_inside >= 0.95

    line = CENTRE + uv[:, :1] * e1
    ell = enclosing_ellipsoid(line)
    assert ell.volume == 0.0 and np.all(ell.radii[1:] == 0.0) and ell.radii[0] > 0.0
    assert abs(ell.axes[0] @ e1) == pytest.approx(1.0, abs=1e-9)

    ell = enclosing_ellipsoid(np.tile(CENTRE, (10, 1)))
    assert ell.volume == 0.0 and np.all(ell.radii == 0.0) and ell.fraction_inside == 1.0
    np.testing.assert_allclose(ell.centre, CENTRE, rtol=1e-14)


@pytest.mark.parametrize("points, match", [
    (np.zeros((3, 3)), "at least 4 points, got 3"),
    (np.zeros((10, 2)), r"shape \(n, 3\), got \(10, 2\)"),
    (np.zeros(12), r"shape \(n, 3\), got \(12,\)"),
    (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.nan], [1, 1, 1]]), "non-finite .* row 3"),
    (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [np.inf, 1, 1]]), "non-finite .* row 4"),
])
def test_bad_points_are_rejected(points, match):
    with pytest.raises(ValueError, match=match):
        enclosing_ellipsoid(points)


@pytest.mark.parametrize("fraction", [0.0, -0.1, 1.5, float("nan"), float("inf")])
def test_bad_fraction_is_rejected(fraction):
    with pytest.raises(ValueError, match=f"fraction must be in \\(0, 1\\], got {fraction}"):
        enclosing_ellipsoid(np.random.default_rng(0).standard_normal((20, 3)), fraction)


def test_projected_outline_matches_the_extent_of_the_surface():
    """The outline's extreme coordinates equal those of densely sampled surface points."""
    rng = np.random.default_rng(9)
    axes = rotation(6).T
    radii = np.array([3.0, 1.0, 0.2])
    ell = Ellipsoid(centre=CENTRE, axes=axes, radii=radii, volume=4 / 3 * math.pi * np.prod(radii),
                    fraction_inside=1.0)
    surface = (unit_sphere(rng, 400_000) * radii) @ axes  # relative to the centre
    for dims in ((0, 2), (1, 2), (0, 1)):
        outline = projected_outline(ell, dims, n=3601)
        for k, d in enumerate(dims):
            assert outline[:, k].max() == pytest.approx(surface[:, d].max(), rel=2e-3)
            assert outline[:, k].min() == pytest.approx(surface[:, d].min(), rel=2e-3)
    flat = Ellipsoid(centre=CENTRE, axes=np.eye(3), radii=np.array([2.0, 0.0, 0.0]), volume=0.0, fraction_inside=1.0)
    outline = projected_outline(flat, (0, 2))
    assert np.all(np.isfinite(outline)) and np.abs(outline[:, 0]).max() == pytest.approx(2.0)
    assert np.all(outline[:, 1] == 0.0)


# ---------------------------------------------------------------------------- the study
G = 9.81  # m/s2


@pytest.fixture(scope="module")
def study(fmu_paths, tmp_path_factory):
    """A short study: 40 s of none and simplified_sheave, the first 10 s left out."""
    from towcable_fmu.analysis.compensation_study import run_study

    return run_study(["none", "simplified_sheave"], duration=40.0, step=0.01,
                     output_dir=tmp_path_factory.mktemp("study"), settle=10.0, fmus=fmu_paths, verbose=False)


def full_scale_table() -> dict:
    path = Path(towcable_fmu.__file__).parent / "builtin_scenes" / "full_scale.toml"
    return tomllib.loads(path.read_text(encoding="utf-8"))


def test_study_writes_table_csv_and_plots(study):
    files = study.files
    for key in ("table", "csv", "track", "tension_time", "tension_distribution", "payout"):
        assert files[key].is_file() and files[key].stat().st_size > 0, key
    for key in ("track", "tension_time", "tension_distribution", "payout"):
        assert files[key].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", key
    table = files["table"].read_text(encoding="utf-8")
    assert "`none`" in table and "`simplified_sheave`" in table and "ellipsoid.volume" in table
    with open(files["csv"], newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["algorithm"] for r in rows] == ["none", "simplified_sheave"]
    assert rows[0]["ellipsoid.volume_reduction [%]"] == "0"
    assert float(rows[1]["ellipsoid.volume [m3]"]) == pytest.approx(
        study.runs["simplified_sheave"].ellipsoid.volume, rel=1e-9)
    assert float(rows[1]["tension.sheave.mean [N]"]) > 0.0


def test_study_tension_at_the_body_balances_weight_lift_and_drag(study):
    """Mean force of the cable on the towed body = |net weight + lift + drag| of the body at
    the tow speed (closed form from the scene's numbers). Within 3 %: the oscillation changes
    the mean drag and lift only to second order in the body's velocity (a few cm/s here)."""
    scene = full_scale_table()
    body, water = scene["towbody"], scene["water"]
    q = 0.5 * water["density"] * sum(v * v for v in water["current"]["velocity"])  # Pa
    drag = sum(q * part["area"][0] * part["drag_coefficient"][0] for part in body["parts"])
    lift = q * body["lift"]["area"] * body["lift"]["coefficient"]
    expected = math.hypot(body["net_weight"] + lift, drag)
    for run in study.runs.values():
        assert run.stats["tension.towbody.mean"] == pytest.approx(expected, rel=0.03), run.algorithm


def test_study_tension_at_the_sheave_exceeds_the_body_by_weight_and_drag(study):
    """Going up a trailing cable the tension grows by the wet weight per metre times the rise
    plus the tangential drag (positive: the flow runs down along the cable). So the mean
    difference sheave - body is more than w_wet (z_sheave - z_body), and within 10 % of the
    static difference (same weight and drag, no waves; the t = 0 sample is the static
    equilibrium the co-simulation starts from)."""
    scene = full_scale_table()
    seg = scene["cable"]["segments"][0]
    rho = scene["water"]["density"]
    w_wet = (seg["mass_per_length"] - rho * math.pi * seg["diameter"] ** 2 / 4.0) * G  # N/m
    z_sheave = scene["sheave"]["position"][2]
    for run in study.runs.values():
        s, stats = run.series, run.stats
        rise = z_sheave - float(np.mean(s["towbody.z"][run.window]))
        difference = stats["tension.sheave.mean"] - stats["tension.towbody.mean"]
        assert difference > w_wet * rise, run.algorithm
        static = s["tension.sheave"][0] - s["tension.towbody"][0]
        assert difference == pytest.approx(static, rel=0.10), run.algorithm
        assert stats["tension.sheave.min"] <= stats["tension.sheave.p01"] <= stats["tension.sheave.mean"] \
            <= stats["tension.sheave.p99"] <= stats["tension.sheave.max"]


def test_study_payout_is_zero_without_compensation_and_follows_the_setpoint_with(study):
    none, comp = study.runs["none"], study.runs["simplified_sheave"]
    comp_range = comp.stats["winch.payout.range"]
    assert comp_range > 0.2  # m: the sheave heaves about +-1 m in this sea
    assert none.stats["winch.payout.range"] < 0.02 * comp_range
    np.testing.assert_array_equal(none.payout_setpoint, 0.0)
    payout, setpoint = comp.series["winch.payout"][comp.window], comp.payout_setpoint[comp.window]
    assert np.corrcoef(payout, setpoint)[0, 1] > 0.99
    assert comp.stats["winch.payout.tracking_rms"] < 0.1 * np.std(setpoint)


def test_study_compensation_reduces_the_ellipsoid(study):
    none, comp = study.runs["none"], study.runs["simplified_sheave"]
    assert none.stats["ellipsoid.volume_reduction"] == 0.0
    assert comp.stats["ellipsoid.volume_reduction"] == pytest.approx(
        100.0 * (1.0 - comp.ellipsoid.volume / none.ellipsoid.volume))
    assert comp.ellipsoid.volume < none.ellipsoid.volume
    assert comp.stats["towbody.depth_std"] < none.stats["towbody.depth_std"]
    for run in study.runs.values():
        assert run.stats["ellipsoid.fraction_inside"] >= 0.95
        assert 0.0 <= run.stats["contact.detached.share"] <= 100.0
        assert run.stats["wall_time"] > 0.0


def test_cli_study_compensation_arguments():
    from towcable_fmu.cli import build_parser, main

    args = build_parser().parse_args(["study-compensation"])
    assert args.algorithms == ["none", "simplified_sheave", "rigorous_sheave"]
    assert (args.duration, args.step, args.output) == (300.0, 0.01, "out/compensation")
    args = build_parser().parse_args(["study-compensation", "--algorithms", "none", "rigorous_sheave",
                                      "--duration", "60"])
    assert args.algorithms == ["none", "rigorous_sheave"] and args.duration == 60.0
    with pytest.raises(SystemExit):
        build_parser().parse_args(["study-compensation", "--algorithms", "magic"])
    assert main(["study-compensation", "--duration", "10", "--settle", "20", "--quiet"]) == 2


def test_study_rejects_bad_settings():
    from towcable_fmu.analysis.compensation_study import run_study

    with pytest.raises(SceneError, match="settle"):
        run_study(["none"], duration=10.0, settle=-1.0, verbose=False)
    with pytest.raises(SceneError, match="algorithms"):
        run_study(["none", "none"], duration=10.0, verbose=False)
    with pytest.raises(SceneError, match="fraction"):
        run_study(["none"], duration=10.0, settle=1.0, fraction=0.0, verbose=False)


def test_study_compares_a_constant_tension_winch(fmu_paths, tmp_path):
    """The constant-tension winch in the study: its target defaults to the static winch
    tension, which the run's mean tension then holds (integral action), and it pays out
    to take up part of the heave: less tension variation at the sheave than no
    compensation in the same sea."""
    from towcable_fmu.analysis.compensation_study import run_study
    from towcable_fmu.ancf.simulation import Simulation

    result = run_study(["none", "constant_tension"], duration=40.0, step=0.01, output_dir=tmp_path, settle=10.0,
                       fmus=fmu_paths, verbose=False)
    target = Simulation.from_scene("full_scale").initialize()["tension.winch"]
    run = result.runs["constant_tension"]
    assert np.mean(run.series["tension.winch"][run.window]) == pytest.approx(target, rel=0.01)
    assert run.stats["tension.sheave.std"] < 0.8 * result.runs["none"].stats["tension.sheave.std"]
    assert run.stats["winch.payout.range"] > 0.1
    assert f"target {target:.6g} N" in result.files["table"].read_text(encoding="utf-8")
