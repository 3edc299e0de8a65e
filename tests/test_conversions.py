"""COLMAP and Metashape conversions, each checked by an independent route: SciPy's quaternions and
a hand-written COLMAP pinhole projection; Metashape's projection formula typed in from its manual.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import photolib as pl

W, H, PIX = 6000, 4000, 0.004  # px, px, mm: a 24 × 16 mm format
D = np.diag([1.0, -1.0, -1.0])

angles = st.tuples(*(st.floats(-np.pi, np.pi) for _ in range(2)),
                   st.floats(-1.5, 1.5)).map(lambda a: (a[0], a[2], a[1]))
coords = st.tuples(*(st.floats(-1e4, 1e4) for _ in range(3))).map(np.array)


def _scene(rng, n=200, c=20.0, x0=0.0, y0=0.0, depth=(50.0, 150.0)):
    """Camera (X0, R) and object points whose ideal images fill the format."""
    R = pl.rotation_opk(*rng.uniform(-0.4, 0.4, 3))
    X0 = rng.uniform(-50, 50, 3) + [0.0, 0.0, 100.0]
    xy = np.column_stack([rng.uniform(-12, 12, n), rng.uniform(-8, 8, n)]) - [x0, y0]
    lam = rng.uniform(*depth, n) / c
    X = X0 + lam[:, None] * (np.column_stack([xy, np.full(n, -c)]) @ R.T)
    return X0, R, X


# -- COLMAP -----------------------------------------------------------------------------------
def _colmap_project(X, qvec, tvec, f, cx, cy):
    """COLMAP's SIMPLE_PINHOLE: x_cam = R(q)·X + t, u = f·x/z + cx, v = f·y/z + cy (px, corner
    origin). SciPy's from_quat is scalar-LAST, COLMAP's qvec scalar-first."""
    qw, qx, qy, qz = qvec
    xc = Rotation.from_quat([qx, qy, qz, qw]).apply(X) + tvec
    assert np.all(xc[:, 2] > 0)  # in front: +z in COLMAP's frame
    return np.column_stack([f * xc[:, 0] / xc[:, 2] + cx, f * xc[:, 1] / xc[:, 2] + cy])


@pytest.mark.parametrize("seed", range(5))
def test_colmap_projection_matches_course(seed):
    rng = np.random.default_rng(seed)
    c, x0, y0 = 20.0, 0.05, -0.03
    X0, R, X = _scene(rng, c=c, x0=x0, y0=y0)
    qvec, tvec = pl.colmap_pose_from_exterior(X0, R)
    # COLMAP intrinsics in px, principal point from the top-left corner, y down
    f, cx, cy = c / PIX, W / 2 + x0 / PIX, H / 2 - y0 / PIX
    uv = _colmap_project(X, qvec, tvec, f, cx, cy)
    xy = pl.project(X, X0, R, c, x0, y0)
    uv_course = pl.colmap_from_pixel(pl.pixel_from_image(xy, W, H, PIX))
    np.testing.assert_allclose(uv_course, uv, atol=1e-7)
    # and back: COLMAP pixels → course image coordinates
    np.testing.assert_allclose(pl.image_from_pixel(pl.pixel_from_colmap(uv), W, H, PIX), xy,
                               atol=1e-9)


def test_colmap_nadir_pose_is_180_degrees_about_x():
    q, t = pl.colmap_pose_from_exterior([5.0, 6.0, 100.0], np.eye(3))
    np.testing.assert_allclose(q, [0.0, 1.0, 0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(Rotation.from_quat(np.roll(q, -1)).as_matrix(), D, atol=1e-15)
    np.testing.assert_allclose(t, [-5.0, 6.0, 100.0])


@settings(max_examples=200, deadline=None)
@given(angles, coords)
def test_colmap_round_trip(opk, X0):
    R = pl.rotation_opk(*opk)
    q, t = pl.colmap_pose_from_exterior(X0, R)
    assert q[0] >= 0 and abs(np.linalg.norm(q) - 1) < 1e-12
    # SciPy (scalar last) agrees with R_cv = diag(1, −1, −1)·Rᵀ
    np.testing.assert_allclose(Rotation.from_quat(np.roll(q, -1)).as_matrix(), D @ R.T, atol=1e-12)
    X0b, Rb = pl.exterior_from_colmap_pose(q, t)
    np.testing.assert_allclose(Rb, R, atol=1e-12)
    np.testing.assert_allclose(X0b, X0, atol=1e-12 * (1 + np.abs(X0).max()))


@settings(max_examples=200, deadline=None)
@given(st.tuples(*(st.floats(-1, 1) for _ in range(4))).filter(lambda v: np.linalg.norm(v) > 0.1),
       coords)
def test_colmap_quaternion_sign_ambiguity(v, t):
    q = np.array(v) / np.linalg.norm(v)
    X0a, Ra = pl.exterior_from_colmap_pose(q, t)
    X0b, Rb = pl.exterior_from_colmap_pose(-q, t)
    np.testing.assert_allclose(Ra, Rb, atol=1e-12)
    np.testing.assert_allclose(X0a, X0b, atol=1e-9)
    np.testing.assert_allclose(Ra, (D @ Rotation.from_quat(np.roll(q, -1)).as_matrix()).T,
                               atol=1e-12)
    q2, t2 = pl.colmap_pose_from_exterior(X0a, Ra)
    assert np.allclose(q2, q, atol=1e-9) or np.allclose(q2, -q, atol=1e-9)
    np.testing.assert_allclose(t2, t, atol=1e-9)


def test_colmap_pixel_centre_convention():
    # COLMAP's (0.5, 0.5) is the centre of the top-left pixel, (W/2, H/2) the image centre
    np.testing.assert_allclose(pl.pixel_from_colmap([[0.5, 0.5], [W / 2, H / 2]]),
                               [[0.0, 0.0], [(W - 1) / 2, (H - 1) / 2]])
    np.testing.assert_allclose(pl.image_from_pixel(pl.pixel_from_colmap([W / 2, H / 2]), W, H, PIX),
                               [0.0, 0.0], atol=1e-15)
    uv = np.random.default_rng(1).uniform(0, 100, (10, 2))
    np.testing.assert_allclose(pl.colmap_from_pixel(pl.pixel_from_colmap(uv)), uv)


@pytest.mark.parametrize("qvec, match", [
    ([1.0, 0.0, 0.0], r"qvec has shape \(3,\)"),
    ([1.0, 0.0, np.nan, 0.0], "non-finite"),
    ([2.0, 0.0, 0.0, 0.0], r"not a unit quaternion: \|q\| = 2"),
    ([0.0, 0.0, 0.0, 0.0], "not a unit quaternion"),
    ("abcd", "numeric"),
])
def test_colmap_bad_quaternion(qvec, match):
    with pytest.raises(ValueError, match=match):
        pl.exterior_from_colmap_pose(qvec, [0.0, 0.0, 0.0])


def test_colmap_bad_inputs():
    with pytest.raises(ValueError, match=r"tvec has shape \(2,\)"):
        pl.exterior_from_colmap_pose([1.0, 0, 0, 0], [0.0, 0.0])
    with pytest.raises(ValueError, match="tvec contains a non-finite"):
        pl.exterior_from_colmap_pose([1.0, 0, 0, 0], [0.0, np.inf, 0.0])
    with pytest.raises(ValueError, match="reflection"):
        pl.colmap_pose_from_exterior([0.0, 0.0, 0.0], D @ np.diag([1.0, 1.0, -1.0]) @ D)
    with pytest.raises(ValueError, match="not orthonormal"):
        pl.colmap_pose_from_exterior([0.0, 0.0, 0.0], 2 * np.eye(3))
    with pytest.raises(ValueError, match=r"X0 has shape \(2,\)"):
        pl.colmap_pose_from_exterior([0.0, 0.0], np.eye(3))
    with pytest.raises(ValueError, match=r"uv has shape \(3,\)"):
        pl.pixel_from_colmap([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="uv contains a non-finite"):
        pl.pixel_from_colmap([1.0, np.nan])


# -- Metashape --------------------------------------------------------------------------------
def _metashape_uv(X, X0, R, f, cx, cy, b1=0.0, b2=0.0, k=(0.0, 0.0, 0.0, 0.0), p1=0.0, p2=0.0):
    """Metashape's frame camera, as printed in its manual: camera frame x right, y down, +z
    forward (x_cam = (R·D)ᵀ(X − X0)); u, v px with w/2, h/2 the image centre."""
    xc = (X - X0) @ (R @ D)
    assert np.all(xc[:, 2] > 0)
    x, y = xc[:, 0] / xc[:, 2], xc[:, 1] / xc[:, 2]
    r2 = x**2 + y**2
    K = 1 + k[0] * r2 + k[1] * r2**2 + k[2] * r2**3 + k[3] * r2**4
    xd = x * K + (p1 * (r2 + 2 * x**2) + 2 * p2 * x * y)
    yd = y * K + (p2 * (r2 + 2 * y**2) + 2 * p1 * x * y)
    u = W * 0.5 + cx + xd * f + xd * b1 + yd * b2
    v = H * 0.5 + cy + yd * f
    return np.column_stack([u, v])


def _metashape_xy(uv):
    """Metashape pixels → course image coordinates (mm); centre of the top-left pixel (0.5, 0.5)."""
    return pl.image_from_pixel(uv - 0.5, W, H, PIX)


def _compare(calib, seed=0, n=400):
    rng = np.random.default_rng(seed)
    io = pl.interior_from_metashape(**calib, width=W, height=H, pixel_size=PIX)
    X0, R, X = _scene(rng, n=n, c=io.c, x0=io.x0, y0=io.y0)
    lens = {key: calib.get(key, 0.0) for key in ("cx", "cy", "b1", "b2", "p1", "p2")}
    k = tuple(calib.get(f"k{i}", 0.0) for i in range(1, 5))
    expected = _metashape_xy(_metashape_uv(X, X0, R, calib["f"], k=k, **lens))
    got = pl.project(X, X0, R, io.c, io.x0, io.y0, distortion=io.distortion)
    return io, np.hypot(*(got - expected).T), (X0, R, X, expected)


@pytest.mark.parametrize("calib", [
    dict(f=5000.0, cx=0.0, cy=0.0),
    dict(f=5000.0, cx=17.3, cy=-9.1),
    dict(f=5000.0, cx=17.3, cy=-9.1, b1=3.0, b2=5.0),
    dict(f=4200.0, cx=-4.0, cy=6.5, b1=-2.5, b2=-7.0),
])
def test_metashape_exact_without_lens_terms(calib):
    io, err, _ = _compare(calib)
    assert io.exact and io.approximate == ""
    assert io.c == pytest.approx(calib["f"] * PIX)
    assert io.x0 == pytest.approx(calib["cx"] * PIX) and io.y0 == pytest.approx(-calib["cy"] * PIX)
    assert err.max() < 1e-9  # mm


def test_metashape_b2_only_gives_negative_c2():
    f, b2 = 5000.0, 5.0
    io, err, (X0, R, X, expected) = _compare(dict(f=f, cx=0.0, cy=0.0, b2=b2))
    p = io.distortion.params
    assert p["C1"] == 0.0 and p["C2"] == pytest.approx(-b2 / f, rel=1e-12) and p["C2"] < 0
    assert err.max() < 1e-9
    # the other sign is visibly wrong: ~0.001·8 mm = 8 µm at the format edge
    wrong = pl.Distortion(C2=+b2 / f)
    bad = np.hypot(*(pl.project(X, X0, R, io.c, distortion=wrong) - expected).T)
    assert bad.max() > 5e-3


def test_metashape_audit_case_b1_b2():
    """The audit's case: b1 = 3 px, b2 = 5 px, f = 5000 px. C2 = −b2/(f + b1) is exact; the
    first-order −b2/f is off by nanometres, +b2/f by 2·(b2/f)·|y'| (16 µm at the 8 mm edge)."""
    f, b1, b2 = 5000.0, 3.0, 5.0
    io, err, (X0, R, X, expected) = _compare(dict(f=f, cx=0.0, cy=0.0, b1=b1, b2=b2))
    p = io.distortion.params
    assert p["C1"] == pytest.approx(b1 / (f + b1)) and p["C2"] == pytest.approx(-b2 / (f + b1))
    assert err.max() < 1e-9

    def worst(C1, C2):
        xy = pl.project(X, X0, R, io.c, distortion=pl.Distortion(C1=C1, C2=C2))
        return np.hypot(*(xy - expected).T).max()

    assert worst(b1 / f, -b2 / f) < 2e-5  # first order: within 0.02 µm
    assert worst(b1 / f, +b2 / f) > 8e-3  # the old docs' sign: ~16 µm at the corners


FITTED = [
    dict(f=5000.0, cx=0.0, cy=0.0, k1=-0.1, k2=0.05, k3=-0.01),
    dict(f=5000.0, cx=12.0, cy=-8.0, k1=-0.1, k2=0.05, k3=-0.01, p1=1e-4, p2=-2e-4),
    dict(f=5000.0, cx=12.0, cy=-8.0, k1=-0.1, k4=0.02),
    dict(f=5000.0, cx=-20.0, cy=15.0, k1=0.08, k2=-0.02, p1=-3e-4, p2=1e-4, b1=3.0, b2=5.0),
    dict(f=3500.0, cx=3.0, cy=4.0, k1=-0.2, k2=0.1, k3=-0.02, k4=0.005, b1=-6.0, b2=2.0),
]


@pytest.mark.parametrize("calib", FITTED)
def test_metashape_fitted_within_reported_residual(calib):
    io, err, _ = _compare(calib, seed=3, n=2000)
    assert not io.exact and "least-squares" in io.approximate
    assert ("k4" in io.approximate) == ("k4" in calib)
    assert 0 < io.rms_um <= io.max_um < 5.0
    # residual m − Δ(m) − u (ideal domain) maps to the measured domain by (I − ∂Δ/∂m)⁻¹ ≈ I;
    # between the grid nodes the residual stays close to its grid maximum
    assert err.max() * 1000 <= 1.25 * io.max_um + 1e-6


def test_metashape_reuses_opencv_route_with_p1_p2_swapped():
    k1, k2, k3, p1, p2 = -0.1, 0.05, -0.01, 1e-4, -2e-4
    io = pl.interior_from_metashape(5000.0, 0.0, 0.0, W, H, PIX, k1=k1, k2=k2, k3=k3, p1=p1, p2=p2)
    d, fit = pl.Distortion.from_opencv((k1, k2, p2, p1, k3), io.c, W * PIX / 2, H * PIX / 2)
    for key in ("A1", "A2", "A3", "B1", "B2"):
        assert io.distortion.params[key] == pytest.approx(d.params[key], rel=1e-6, abs=1e-18)
    assert io.max_um == pytest.approx(fit.max_um, rel=1e-6)


def test_metashape_non_square_pixels_exact_affinity():
    # x pixel 1 % wider: the x scale differs from y, C1 = 1 − s_y f/(s_x (f + b1))
    s = (0.00404, 0.004)
    io = pl.interior_from_metashape(5000.0, 0.0, 0.0, W, H, s, b1=3.0)
    assert io.exact
    assert io.distortion.params["C1"] == pytest.approx(1 - 0.004 * 5000 / (0.00404 * 5003))
    assert io.c == pytest.approx(20.0) and io.x0 == 0.0


def test_metashape_transform_round_trip_and_axes():
    R = pl.rotation_opk(0.1, -0.2, 0.3)
    X0 = np.array([1.0, 2.0, 3.0])
    T = pl.metashape_transform_from_exterior(X0, R)
    # Metashape's +z (viewing direction) is the course's −z, its y (down) the course's −y
    np.testing.assert_allclose(T[:3, :3] @ [0, 0, 1], R @ [0, 0, -1], atol=1e-15)
    np.testing.assert_allclose(T[:3, :3] @ [0, 1, 0], R @ [0, -1, 0], atol=1e-15)
    np.testing.assert_allclose(T @ [0, 0, 0, 1], [*X0, 1])
    X0b, Rb = pl.exterior_from_metashape_transform(T)
    np.testing.assert_allclose(Rb, R, atol=1e-15)
    np.testing.assert_allclose(X0b, X0)
    with pytest.raises(ValueError, match="last row"):
        pl.exterior_from_metashape_transform(np.vstack([T[:3], [0, 0, 1, 1]]))
    with pytest.raises(ValueError, match="not orthonormal"):
        pl.exterior_from_metashape_transform(np.diag([2.0, -2.0, -2.0, 1.0]))
    with pytest.raises(ValueError, match=r"T has shape \(3, 3\)"):
        pl.exterior_from_metashape_transform(np.eye(3))


@pytest.mark.parametrize("kwargs, match", [
    (dict(f=0.0), "f must be > 0, got 0.0"),
    (dict(f=-5000.0), "f must be > 0"),
    (dict(f=np.nan), "f must be finite"),
    (dict(cx=np.nan), "cx must be finite"),
    (dict(width=0), "width must be > 0"),
    (dict(pixel_size=-0.004), "pixel_size x must be > 0"),
    (dict(pixel_size=(0.004, 0.004, 0.004)), r"pixel_size has shape \(3,\)"),
    (dict(b1=-5000.0), r"f \+ b1 must be > 0"),
    (dict(k4=np.inf), "k4 must be finite"),
    (dict(p1="x"), "p1 must be a real number"),
    (dict(n=2), "n must be an integer ≥ 3"),
])
def test_metashape_bad_inputs(kwargs, match):
    args = dict(f=5000.0, cx=0.0, cy=0.0, width=W, height=H, pixel_size=PIX) | kwargs
    with pytest.raises(ValueError, match=match):
        pl.interior_from_metashape(**args)
