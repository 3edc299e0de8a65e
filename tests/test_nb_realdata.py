"""photolib.nb.realdata: the tables and figures of the real chessboard camera (chapters 05, 08)."""

from __future__ import annotations

import re

import numpy as np
import pytest

pytest.importorskip("cv2")
rd = pytest.importorskip("photolib.nb.realdata")


@pytest.fixture(scope="module")
def cal():
    return rd.chessboard_calibration()


def test_opencv_radial_distortion_inverts_opencvs_forward_model():
    k, f = (-0.28, 0.044, 0.0, 0.0, 0.12), 530.0
    rho = np.linspace(0.0, 280.0, 15)
    n2 = (rho / f) ** 2
    r = rho * (1 + k[0] * n2 + k[1] * n2**2 + k[4] * n2**3)  # OpenCV: ideal ρ → measured r
    assert np.allclose(rd.opencv_radial_distortion(k, f, r), r - rho, atol=1e-9)


def test_interior_rows_print_two_decimals_and_sigma_ratios(cal):
    rows = rd.interior_rows(cal)
    assert len(rows) == 4 and rows[0].startswith("[px]")
    for row, label in zip(rows[1:], ("c", "x'0", "y'0")):
        assert row.split()[0] == label
        numbers = re.findall(r"[-+]?\d+\.\d+", row)
        assert [len(n.split(".")[1]) for n in numbers] == [2, 2, 2, 2, 1, 1]


def test_opencv_interior_maps_the_pixel_origin(cal):
    K = cal.opencv["K"]
    io = cal.opencv_interior("opencv")
    assert io["x0"] == K[0, 2] - 319.5 and io["y0"] == 239.5 - K[1, 2] and io["c"] == K[0, 0]
    with pytest.raises(ValueError, match="which must be 'opencv' or 'published', got 'cv'"):
        cal.opencv_interior("cv")


def test_r_data_is_the_largest_measured_radius(cal):
    pp = np.array([cal.result.x0, cal.result.y0])
    radii = np.concatenate([np.hypot(*(q - pp).T) for q in cal.xy])
    assert cal.r_data == radii.max() and cal.r_data < np.hypot(319.5, 239.5)


def test_figures(cal):
    fig = rd.plot_real_residuals(cal)
    assert len(fig.axes) == 2 and not fig.stale
    fig2 = rd.plot_real_distortion(cal, n_lines=5)
    ax, ax2 = fig2.axes
    assert len(ax.lines) == 2 * 2 * 5 + 1  # ideal and imaged line per grid line, the format
    assert ax2.get_xlim()[1] <= 1.06 * cal.r_data  # no extrapolation drawn
    import matplotlib.pyplot as plt
    plt.close(fig)
    plt.close(fig2)


def test_plot_corner_marks_the_corner_and_names_a_bad_view(capsys):
    from photolib.grading.notebook import NoParameters
    from photolib.nb import realdata as rd

    fig = rd.plot_corner("left05.jpg", 559.32, 364.66)
    whole, zoom = fig.axes[:2]
    assert whole.lines[0].get_xdata()[0] == 559.32
    assert zoom.get_xlim() == (559.32 - 24, 559.32 + 24)
    with pytest.raises(ValueError, match="left99.jpg"):
        rd.plot_corner("left99.jpg", 1.0, 1.0)
    assert rd.show_task_corner(NoParameters("io.real-corner")) is None
    assert "STUDENT_ID is empty" in capsys.readouterr().out
