"""Rectification with resampling, checked against SciPy and OpenCV as independent routes."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from photolib.rectify import output_grid, rectify_image, sample_image
from photolib.transforms import AffineTransform, ProjectiveTransform


@pytest.fixture
def image():
    rng = np.random.default_rng(7)
    return rng.uniform(0.0, 255.0, size=(40, 50))


def _inside_positions(rng, shape, n=500):
    H, W = shape
    return np.column_stack([rng.uniform(0.0, W - 1.0, n), rng.uniform(0.0, H - 1.0, n)])


@pytest.mark.parametrize("order", [0, 1])
def test_sampling_agrees_with_scipy_map_coordinates(image, order):
    pos = _inside_positions(np.random.default_rng(1), image.shape)
    ours = sample_image(image, pos, order=order)
    # map_coordinates takes (row, col)
    ref = ndimage.map_coordinates(image, [pos[:, 1], pos[:, 0]], order=order, mode="nearest")
    np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-9)


def test_sampling_colour_image_channel_by_channel(image):
    rgb = np.stack([image, 255 - image, image / 2], axis=-1)
    pos = _inside_positions(np.random.default_rng(2), image.shape, 50)
    ours = sample_image(rgb, pos)
    assert ours.shape == (50, 3)
    for k in range(3):
        ref = ndimage.map_coordinates(rgb[..., k], [pos[:, 1], pos[:, 0]], order=1)
        np.testing.assert_allclose(ours[:, k], ref, atol=1e-9)


def test_outside_positions_get_the_fill_value(image):
    pos = np.array([[-0.01, 3.0], [49.01, 3.0], [3.0, 39.5], [np.nan, 2.0]])
    assert sample_image(image, pos, fill=-1.0).tolist() == [-1.0] * 4
    # nearest neighbour reaches half a pixel beyond the outer centres
    near = sample_image(image, [[-0.49, 0.0], [49.49, 39.49]], order=0, fill=-1.0)
    assert near.tolist() == [image[0, 0], image[39, 49]]


def test_output_grid_convention():
    g = output_grid((3, 4), (100.0, 50.0), 0.25)
    assert g.shape == (3, 4, 2)
    assert g[0, 0].tolist() == [100.0, 50.0]
    assert g[2, 3].tolist() == [100.75, 49.5]  # col → +X, row → −Y


def test_projective_rectification_agrees_with_opencv(image):
    cv2 = pytest.importorskip("cv2")
    # object (X, Y) in m → source pixel (col, row): a tilted view of a façade
    obj = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]])
    pix = np.array([[3.0, 36.0], [46.0, 33.0], [41.0, 4.0], [6.0, 8.0]])
    to_pixel = ProjectiveTransform.from_estimate(obj, pix)
    shape, origin, d = (30, 40), (0.0, 3.0), 0.1
    ours = rectify_image(image, to_pixel, shape, origin=origin, pixel_size=d, fill=np.nan)
    # OpenCV: dst(col, row) = src(M·(col, row, 1)) with WARP_INVERSE_MAP; M = H_obj→pix · A_out→obj
    A = np.array([[d, 0.0, origin[0]], [0.0, -d, origin[1]], [0.0, 0.0, 1.0]])
    M = to_pixel.matrix @ A
    ref = cv2.warpPerspective(image.astype(np.float32), M, (shape[1], shape[0]),
                              flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                              borderMode=cv2.BORDER_CONSTANT, borderValue=np.nan)
    inside = np.isfinite(ours) & np.isfinite(ref)
    assert inside.mean() > 0.9
    # OpenCV quantises the interpolation weights to 1/32 pixel: agreement to ~1 % of the range
    assert np.max(np.abs(ours[inside] - ref[inside])) < 255 / 32 * 0.6


def test_rectification_agrees_with_scipy_on_the_same_positions(image):
    to_pixel = AffineTransform(a0=2.0, a1=1.8, a2=0.3, b0=35.0, b1=0.2, b2=-1.7)
    shape, origin, d = (15, 20), (0.0, 0.0), 1.0
    ours = rectify_image(image, to_pixel, shape, origin=origin, pixel_size=d, order=1, fill=-5.0)
    g = output_grid(shape, origin, d).reshape(-1, 2)
    cr = to_pixel(g)
    ref = ndimage.map_coordinates(image, [cr[:, 1], cr[:, 0]], order=1, mode="constant",
                                  cval=-5.0).reshape(shape)
    H, W = image.shape
    inside = ((cr[:, 0] >= 0) & (cr[:, 0] <= W - 1) & (cr[:, 1] >= 0)
              & (cr[:, 1] <= H - 1)).reshape(shape)
    assert inside.any() and (~inside).any()
    np.testing.assert_allclose(ours[inside], ref[inside], atol=1e-9)
    assert np.all(ours[~inside] == -5.0)


def test_identity_rectification_reproduces_the_image(image):
    to_pixel = AffineTransform(a0=0.0, a1=1.0, b0=0.0, b2=-1.0)  # col = X, row = −Y
    out = rectify_image(image, to_pixel, image.shape, origin=(0.0, 0.0), pixel_size=1.0)
    np.testing.assert_array_equal(out, image)
    out0 = rectify_image(image.astype(np.uint8), to_pixel, image.shape, origin=(0.0, 0.0),
                         pixel_size=1.0, order=0)
    np.testing.assert_array_equal(out0, image.astype(np.uint8))


@pytest.mark.parametrize("kwargs, match", [
    ({"out_shape": (0, 5)}, "out_shape"),
    ({"out_shape": (2.5, 5)}, "out_shape"),
    ({"origin": (1.0,)}, "origin"),
    ({"pixel_size": -1.0}, "pixel_size"),
    ({"pixel_size": "big"}, "pixel_size"),
    ({"order": 3}, "order"),
    ({"transform": "not callable"}, "transform must be callable"),
    ({"image": np.zeros(5)}, "image has shape"),
    ({"image": np.array([["a"]])}, "image must be real numeric"),
    ({"transform": lambda p: p[:, :1]}, "transform returned shape"),
])
def test_bad_input_names_the_argument(image, kwargs, match):
    args = {"image": image, "transform": AffineTransform(), "out_shape": (4, 5),
            "origin": (0.0, 0.0), "pixel_size": 1.0}
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        rectify_image(args.pop("image"), args.pop("transform"), args.pop("out_shape"), **args)
