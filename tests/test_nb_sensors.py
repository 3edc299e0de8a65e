"""Chapters 01 and 03 notebook helpers: the widgets' callbacks and figures, called directly.

Expected values come by other routes: NumPy rounding written out for the quantiser, the FFT
of the samples for the alias, OpenCV's demosaic for the false colours, ``photolib.project``
for the footprint, and counting footprints over the block for the flight plan.
"""

from __future__ import annotations

import cv2
import matplotlib
import numpy as np
import pytest
import sympy as sp

matplotlib.use("Agg")

import photolib as pl  # noqa: E402
from photolib.derive import sensors as ds  # noqa: E402
from photolib.nb import intro as ni  # noqa: E402
from photolib.nb import sensors as ns  # noqa: E402

from .explorer_checks import assert_explorer_widget, assert_every_value_redraws, moves  # noqa: E402


pytestmark = pytest.mark.usefixtures("close_figures")


# -- chapter 03 -----------------------------------------------------------------------------------

@pytest.mark.parametrize("bits", [1, 3, 8])
def test_quantisation_report_rounds_to_the_levels(bits):
    rep = ns.quantisation_report(bits)
    levels = 2**bits - 1
    np.testing.assert_allclose(rep["quantised"], np.round(rep["signal"] * levels) / levels,
                               atol=1e-15)
    np.testing.assert_allclose(rep["image"], np.round(ns.demo_image() * levels) / levels,
                               atol=1e-15)
    assert rep["sigma_model"] == pytest.approx(1 / levels / np.sqrt(12), rel=1e-14)
    assert f"2<sup>{bits}</sup> = {2**bits}" in rep["html"]


def test_quantisation_error_approaches_the_uniform_model_for_fine_steps():
    # for steps much finer than the signal's variation the error is nearly uniform; its RMS
    # then lies within the sampling error of 400 uniform values (relative SE ≈ 0.045)
    rep = ns.quantisation_report(8)
    assert abs(rep["sigma_measured"] / rep["sigma_model"] - 1) < 4 * 0.045


@pytest.mark.parametrize("f, ff", [(40.0, 1.0), (130.0, 0.5), (260.0, 0.2), (100.0, 1.0)])
def test_aliasing_report_alias_goes_through_the_samples(f, ff):
    rep = ns.aliasing_report(f, ff)
    at_pixels = np.interp(rep["pixel_um"], rep["x_um"], rep["alias"])
    # linear interpolation of a cosine on the fine grid: error ≤ (2π f_a h)²/8
    h = (rep["x_um"][1] - rep["x_um"][0]) * 1e-3
    bound = (2 * np.pi * rep["f_alias"] * h) ** 2 / 8 + 1e-12
    assert np.max(np.abs(at_pixels - rep["samples"])) <= bound
    assert rep["aliased"] == (f > 100.0)
    assert rep["mtf"] == pytest.approx(np.sinc(f * ns.PITCH_MM * np.sqrt(ff)), rel=1e-14)


def test_aliasing_report_alias_is_the_fft_peak():
    rep = ns.aliasing_report(170.0, 1.0, n=500)
    spectrum = np.abs(np.fft.rfft(rep["samples"]))
    peak = np.fft.rfftfreq(500, ns.PITCH_MM)[np.argmax(spectrum)]
    assert peak == pytest.approx(rep["f_alias"]) == pytest.approx(30.0)


def test_bayer_report_false_colour_as_opencv_sees_it():
    for period in (2.5, 6.0, 24.0):
        rep = ns.bayer_report(period)
        mosaic8 = np.rint(255 * rep["mosaic"]).astype(np.uint8)
        theirs = cv2.cvtColor(mosaic8, cv2.COLOR_BayerBG2RGB).astype(float)[1:-1, 1:-1] / 255
        false = np.sqrt(np.mean((theirs - theirs.mean(axis=-1, keepdims=True)) ** 2))
        assert abs(rep["false_colour"] - false) < 2 / 255
    assert ns.bayer_report(24.0)["false_colour"] < 0.05 < ns.bayer_report(2.5)["false_colour"]


def test_quantisation_explorer_updates():
    e = ns.QuantisationExplorer()
    assert e.live.output.outputs[0]["data"]["image/png"]
    assert moves(e, "bits", 6.0) == (True, True)
    assert "64 grey values" in e.html.value
    assert_explorer_widget(e, "quantisation explorer")


def test_aliasing_explorer_updates():
    e = ns.AliasingExplorer()
    assert moves(e, "frequency", 150.0) == (True, True)
    assert "aliased" in e.html.value and e.report["f_alias"] == 50.0
    assert moves(e, "fill_factor", 0.3) == (True, True)
    np.testing.assert_allclose(e._mtf.get_ydata(), pl.sensors.pixel_mtf(e._f, 0.005, 0.3))
    assert_explorer_widget(e, "sampling and aliasing explorer")


def test_bayer_explorer_updates():
    e = ns.BayerExplorer()
    assert moves(e, "period_px", 3.0) == (True, True)
    assert e.report["false_colour"] > 0.05
    assert "photolib-explorer" in e.widget._dom_classes


def test_static_figures_of_chapter_03():
    fig = ns.plot_snr()
    assert len(fig.axes[0].lines) == 4
    y = fig.axes[0].lines[0].get_ydata()
    assert np.all(np.diff(y) > 0)                       # SNR rises with the signal
    fig = ns.plot_mtf()
    assert len(fig.axes[0].lines) == 4
    fig = ns.plot_bayer(ns.stripe_chart(4.0, 16))
    assert len(fig.axes) == 3


# -- chapter 01 -----------------------------------------------------------------------------------

@pytest.mark.parametrize("c, logd, pixel", [(100.0, 3.0, 6.0), (24.0, 1.0, 4.0), (8.0, -0.3, 2.0)])
def test_scale_report_footprint_projects_onto_the_sensor(c, logd, pixel):
    rep = ni.scale_report(c, logd, pixel)
    H = 10.0**logd
    w, h = rep["footprint"]
    xy = pl.project([[-w / 2, h / 2, 0.0], [w / 2, -h / 2, 0.0]], [0.0, 0.0, H], np.eye(3), c)
    half = np.array(ni.SENSOR_PX) * pixel / 1000 / 2
    np.testing.assert_allclose(np.abs(xy), [half, half], rtol=1e-8)
    assert rep["scale_number"] == pytest.approx(H * 1000 / c, rel=1e-14)
    assert rep["gsd"] == pytest.approx(w / ni.SENSOR_PX[0], rel=1e-8)


def test_configuration_names_the_range():
    assert ni.configuration(2.0).startswith("close range")
    assert "UAV" in ni.configuration(80.0) and "close range" in ni.configuration(80.0)
    assert ni.configuration(250.0) == "between the usual configurations"


@pytest.mark.parametrize("H, p, q", [(1500.0, 60.0, 30.0), (800.0, 80.0, 20.0),
                                     (3000.0, 50.0, 0.0)])
def test_flight_report_footprints_cover_the_block_in_stereo(H, p, q):
    rep = ni.flight_report(H, p, q)
    fb = rep["plan"]
    x, y = rep["outlines"]
    boxes = np.stack([x, y], axis=1).reshape(-1, 6, 2)[:, :4]
    lo, hi = boxes.min(axis=1), boxes.max(axis=1)
    gx, gy = np.meshgrid(np.linspace(0, ni.BLOCK_M[0], 81), np.linspace(0, ni.BLOCK_M[1], 61))
    pts = np.column_stack([gx.ravel(), gy.ravel()])
    inside = np.all((pts[:, None] >= lo[None] - 1e-6) & (pts[:, None] <= hi[None] + 1e-6),
                    axis=2)
    per_strip = inside.reshape(len(pts), fb.strips, fb.images_per_strip).sum(axis=2)
    assert np.all(per_strip.max(axis=1) >= 2)          # every point in a stereo model
    assert len(boxes) == fb.images == len(rep["centres"])
    assert f"{fb.images} images" in rep["html"]


def test_image_scale_explorer_updates():
    e = ni.ImageScaleExplorer()
    assert moves(e, "log_distance", 1.0) == (True, True)
    assert "close range" in e.html.value
    assert moves(e, "c_mm", 50.0) == (True, True)
    np.testing.assert_allclose(e._line.get_ydata(), 4e-3 * e._H / 50.0)
    assert_explorer_widget(e, "image scale and GSD explorer")


def test_flight_block_explorer_updates():
    e = ni.FlightBlockExplorer()
    images = e.report["plan"].images
    assert moves(e, "overlap_pct", 80.0) == (True, True)
    assert e.report["plan"].images > images
    assert moves(e, "height_m", 3000.0) == (True, True)
    assert "photolib-explorer" in e.widget._dom_classes


def test_static_figures_of_chapter_01():
    fig = ni.plot_timeline()
    assert len(fig.axes[0].texts) >= len(ni.HISTORY) + 3
    assert any("1858" in t.get_text() for t in fig.axes[0].texts)
    fig = ni.plot_process()
    assert sum("products" in t.get_text() for t in fig.axes[0].texts) == 1


@pytest.mark.parametrize("cls, name, values", [
    (ns.QuantisationExplorer, "bits", (2.0, 7.0)),
    (ns.AliasingExplorer, "frequency", (70.0, 150.0)),
    (ns.BayerExplorer, "period_px", (3.0, 9.0)),
    (ni.ImageScaleExplorer, "log_distance", (1.0, 3.5)),
    (ni.FlightBlockExplorer, "height_m", (900.0, 2500.0)),
])
def test_every_value_redraws(cls, name, values):
    assert_every_value_redraws(cls, name, values)


# -- image pyramid and exposure (chapter 03) ------------------------------------------------
def test_image_pyramid_matches_opencv_area_resampling():
    rng = np.random.default_rng(5)
    img = rng.uniform(0, 1, (64, 48)).astype(np.float64)
    levels = ns.image_pyramid(img)
    g = img
    for level in levels[1:5]:
        g = cv2.resize(g, (g.shape[1] // 2, g.shape[0] // 2), interpolation=cv2.INTER_AREA)
        np.testing.assert_allclose(level, g, atol=1e-12)


def test_image_pyramid_odd_sizes_and_colour():
    img = np.random.default_rng(1).uniform(0, 1, (7, 5, 3))
    levels = ns.image_pyramid(img)
    assert [lv.shape[:2] for lv in levels] == ns.pyramid_shapes(img.shape)
    assert all(lv.shape[2] == 3 for lv in levels)
    # the last, odd row is repeated: its block mean is the mean of the row's two pixels
    np.testing.assert_allclose(levels[1][3, 0], img[6, 0:2].mean(axis=0))


def test_pyramid_storage_approaches_one_third():
    shapes = ns.pyramid_shapes((4096, 4096))
    extra = sum(r * c for r, c in shapes[1:]) / 4096**2
    n = len(shapes) - 1
    assert extra == pytest.approx(float(ds.pyramid_overhead(n)), abs=1e-15)
    assert extra < float(ds.pyramid_overhead()) == pytest.approx(1 / 3)
    assert sp.Rational(1, 3) - ds.pyramid_overhead(n) == sp.Rational(1, 3) / 4**n


@pytest.mark.parametrize("bad", [(0, 3), (3,), "ab"])
def test_pyramid_shapes_rejects_bad_shapes(bad):
    with pytest.raises(ValueError, match="shape"):
        ns.pyramid_shapes(bad)


def test_image_pyramid_rejects_bad_rank():
    with pytest.raises(ValueError, match=r"\(5,\)"):
        ns.image_pyramid(np.zeros(5))


def test_exposure_report_against_direct_quantisation():
    scene = np.linspace(0.0, 1.0, 101)
    for factor in (0.25, 1.0, 2.0):
        rep = ns.exposure_report(factor, scene, full_well_e=1000.0, bits=8)
        expected = np.clip(np.rint(factor * scene * 255), 0, 255)
        np.testing.assert_array_equal(rep["dn"], expected)
        assert rep["clipped"] == pytest.approx(np.mean(factor * scene > 1.0))
    with pytest.raises(ValueError, match="-1"):
        ns.exposure_report(-1)
