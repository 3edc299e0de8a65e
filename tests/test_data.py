"""photolib.data: the loaders of the real image sets, their metadata, and no downloads."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import photolib.data as D

ROOT = Path(__file__).resolve().parents[1]


def test_import_photolib_loads_no_data_package():
    code = ("import sys, photolib, photolib.data, photolib.glossary; "
            "print(sorted(m for m in ('mvtbdata', 'skimage', 'PIL', 'cv2') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=ROOT)
    assert out.stdout.strip() == "[]"


def test_glossary_still_reads_its_csv_from_the_data_package():
    from photolib.glossary import load_glossary
    assert any(t.en == "camera constant" for t in load_glossary())


def test_missing_package_names_the_install_command(monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "mvtbdata" else real(name, *a))
    with pytest.raises(D.DataPackageMissing, match=r"'mvtb-data'.*pip install -c constraints.txt"):
        D.chessboard()
    with pytest.raises(ImportError):  # DataPackageMissing is an ImportError
        D.church()


def test_bad_choices_are_named():
    with pytest.raises(ValueError, match="name must be one of .*'rocks2'.*got 'rocks'"):
        D.stereo_pair("rocks")
    with pytest.raises(ValueError, match="holdout must be True or False, got 'yes'"):
        D.campus(holdout="yes")


def test_chessboard_images_and_published_calibration():
    cb = D.chessboard()
    assert len(cb) == 14 and cb.files[0] == "left01.jpg" and cb.files[-1] == "left14.jpg"
    assert all(im.shape == (480, 640) and im.dtype == np.uint8 for im in cb.images)
    assert cb.sizes == ((640, 480),) * 14 and cb.pixel_pitch_mm is None
    assert cb.licence == "MIT" and "mvtb-data 1.6.1" in cb.attribution
    cal = cb.calibration
    assert (cal.width, cal.height, cal.board, cal.square_mm, cal.n_frames) == (640, 480, (9, 6),
                                                                                 25.0, 13)
    assert cal.flags == 2 and cal.per_view_rms_px.shape == (13,) and cal.extrinsics.shape == (13, 6)
    # the values printed in left_intrinsics.yml
    assert cal.camera_matrix[0, 0] == cal.camera_matrix[1, 1] == 5.3591573396163199e+02
    assert cal.camera_matrix[0, 2] == 3.4228315473308373e+02
    assert cal.distortion[0] == -2.6637260909660682e-01 and cal.rms_px == 3.9259098975581364e-01
    io = cal.interior()
    assert io["x0"] == cal.camera_matrix[0, 2] - 319.5
    assert io["y0"] == 239.5 - cal.camera_matrix[1, 2]
    # the object frame: corner k = 9j + i at X = 25·i, Y = −25·j (the next row lies at −Y)
    P = cb.extra["object_points"]
    assert P.shape == (54, 3) and P[10].tolist() == [25.0, -25.0, 0.0]
    assert (P[1] - P[0]).tolist() == [25.0, 0.0, 0.0] and (P[9] - P[0]).tolist() == [0, -25, 0]


def test_motorcycle_is_read_from_the_installed_wheel_without_importing_skimage():
    code = ("import sys, numpy as np, photolib.data as D; m = D.motorcycle(); "
            "print('skimage' in sys.modules, 'pooch' in sys.modules, m.left.shape, "
            "int(np.isnan(m.disparity).sum()))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=ROOT)
    assert out.stdout.startswith("False False (500, 741, 3)")  # neither skimage nor pooch
    spec = importlib.util.find_spec("skimage")
    for n in ("motorcycle_left.png", "motorcycle_right.png", "motorcycle_disp.npz"):
        assert (Path(next(iter(spec.submodule_search_locations))) / "data" / n).is_file()


def test_motorcycle_disparity_convention_and_depth():
    m = D.motorcycle()
    assert m.left.shape == m.right.shape == (500, 741, 3) and m.disparity.shape == (500, 741)
    assert m.calibration.f_px == 994.978 and m.calibration.baseline_mm == 193.001
    assert m.calibration.doffs_px == 31.086
    d = m.disparity
    assert np.isnan(d).any() and not np.isinf(d).any()
    # left (row, col) shows what right (row, col − d) shows: the grey values agree far better
    # than with the opposite sign or no shift
    L, R = m.left.astype(float).mean(axis=2), m.right.astype(float).mean(axis=2)
    r, c = np.nonzero(np.isfinite(d))
    err = {}
    for sign in (-1, 0, 1):
        cc = np.rint(c + sign * d[r, c]).astype(int)
        ok = (cc >= 0) & (cc < L.shape[1])
        err[sign] = float(np.mean(np.abs(L[r[ok], c[ok]] - R[r[ok], cc[ok]])))
    assert err[-1] < 0.5 * min(err[0], err[1])
    z = m.calibration.depth_mm(d)
    assert np.all(np.isnan(z) == np.isnan(d))
    assert 1000.0 < np.nanmin(z) < np.nanmax(z) < 10000.0  # a motorcycle a few metres away


@pytest.mark.parametrize("loader, n, first_size, mode", [
    (D.mosaic, 10, (1279, 1023), 2),
    (D.building2, 3, (1181, 851), 2),
    (D.church, 1, (1280, 851), 3),
    (D.eiffel, 2, (1280, 851), 3),
    (D.yellowtargets, 1, (640, 480), 3),
    (D.campus, 20, (640, 426), 3),
])
def test_image_sets(loader, n, first_size, mode):
    s = loader()
    assert len(s) == n == len(s.files) == len(s.sizes)
    assert s.sizes[0] == first_size and s[0].ndim == mode and s[0].dtype == np.uint8
    assert all(im.shape[1::-1] == size for im, size in zip(s.images, s.sizes))
    assert s.licence == "MIT" and s.calibration is None and s.pixel_pitch_mm is None


def test_building2_third_view_drops_its_alpha_and_campus_holdout():
    assert D.building2()[2].shape == (851, 1280, 3)
    h = D.campus(holdout=True)
    assert len(h) == 5 and set(h.files).isdisjoint({f"{n}.png" for n in D.CAMPUS_FILES})


@pytest.mark.slow
@pytest.mark.parametrize("name, size", [("rocks2", (1276, 1110)), ("walls", (3264, 2448))])
def test_stereo_pairs(name, size):
    p = D.stereo_pair(name)
    assert p.size == size and p.left.shape == p.right.shape == (size[1], size[0], 3)
    assert p.calibration is None and p.disparity is None and p.files == (f"{name}-l.png",
                                                                           f"{name}-r.png")


def test_stereo_depth_refuses_nothing_silently():
    cal = D.StereoCalibration(1000.0, 0.0, 0.0, 10.0, 200.0)
    z = cal.depth_mm([90.0, np.nan, -10.0, -20.0])
    assert z[0] == 2000.0 and np.isnan(z[1:]).all()
