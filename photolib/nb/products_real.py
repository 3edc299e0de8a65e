"""Chapter 12 on real photographs: the aerial mosaic and structure from motion (plumbing).

OpenCV is the measuring tool only: ``cv2.ORB_create`` finds and describes features and a
brute-force Hamming matcher with Lowe's ratio test pairs them (the tie points). Everything
photogrammetric — the plane transformations with RANSAC, the chaining, the resampling, the
seam lines, the residuals, the relative orientations and the bundle adjustment — is
photolib's (:mod:`photolib.image_mosaic`, :mod:`photolib.sfm`). ``cv2.findHomography`` is
shown beside photolib's transformation as a side comparison only.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

import photolib as pl
from photolib import image_mosaic as im
from photolib.nb.live import Explorer, LiveFigure, slider
from photolib.rectify import rectify_image

__all__ = ["AERIAL", "DOWNSAMPLE", "MosaicZoom", "aerial_images", "match_features",
           "measure_tie_points", "orb_features",
           "mosaic_block", "opencv_homography", "plot_real_mosaic", "plot_tie_residuals",
           "reduce_image", "residual_rows", "synthetic_precision"]

#: the aerial images of photolib.data.mosaic() used in the chapter (0-based: aerial2-001…004)
AERIAL = (0, 1, 2, 3)
#: block-mean reduction of the aerial images (2 × 2 pixels → 1): a quarter of the pixels
DOWNSAMPLE = 2
#: ORB features per image and Lowe's ratio
N_FEATURES, RATIO = 2500, 0.8
#: RANSAC inlier bound (px of the reduced images): 3 × the ORB precision measured below
THRESHOLD = 2.2


def _cv2():
    import cv2
    return cv2


def reduce_image(image, factor: int = DOWNSAMPLE) -> np.ndarray:
    """Block mean of ``factor × factor`` pixels (uint8 kept).

    Pixel (col, row) of the reduced image is centred at ``factor·col + (factor − 1)/2`` of
    the original (the course's pixel-centre convention).

    >>> reduce_image(np.arange(16, dtype=np.uint8).reshape(4, 4)).tolist()
    [[2, 4], [10, 12]]
    """
    a = np.asarray(image, dtype=float)
    H, W = (a.shape[0] // factor) * factor, (a.shape[1] // factor) * factor
    a = a[:H, :W].reshape(H // factor, factor, W // factor, factor).mean(axis=(1, 3))
    return np.floor(a).astype(np.uint8) if np.asarray(image).dtype == np.uint8 else a


@lru_cache(maxsize=4)
def aerial_images(indices=AERIAL, factor: int = DOWNSAMPLE) -> tuple:
    """The chosen aerial images of :func:`photolib.data.mosaic`, reduced (read-only)."""
    from photolib.data import mosaic
    ms = mosaic()
    out = []
    for i in indices:
        a = reduce_image(ms[i], factor)
        a.setflags(write=False)
        out.append(a)
    return tuple(out)


def orb_features(image, n_features: int = N_FEATURES):
    """ORB keypoints and descriptors of a grey image (OpenCV, the measuring tool)."""
    cv2 = _cv2()
    k, d = cv2.ORB_create(n_features).detectAndCompute(np.ascontiguousarray(image), None)
    if d is None:
        raise ValueError("no ORB features found in the image")
    return k, d


def match_features(f1, f2, ratio: float = RATIO):
    """Tie points ``(p1, p2)`` of two feature sets: Hamming matcher with Lowe's ratio test."""
    cv2 = _cv2()
    (k1, d1), (k2, d2) = f1, f2
    matches = cv2.BFMatcher(cv2.NORM_HAMMING).knnMatch(d1, d2, k=2)
    good = [m[0] for m in matches if len(m) == 2 and m[0].distance < ratio * m[1].distance]
    p1 = np.array([k1[m.queryIdx].pt for m in good], dtype=float).reshape(-1, 2)
    p2 = np.array([k2[m.trainIdx].pt for m in good], dtype=float).reshape(-1, 2)
    return p1, p2


def measure_tie_points(img1, img2, n_features: int = N_FEATURES, ratio: float = RATIO):
    """ORB tie points between two grey images: ``(p1, p2)``, (N, 2) each, (col, row) px.

    OpenCV's keypoint positions have (0, 0) at the centre of the top-left pixel, as the
    course's pixel coordinates. Deterministic for given images.
    """
    return match_features(orb_features(img1, n_features), orb_features(img2, n_features), ratio)


def synthetic_precision(image, seed: int = 0, n_features: int = N_FEATURES):
    """The ORB measurement precision on this image: σ (px) per coordinate and the count.

    The image is resampled by photolib (bilinear) under a known mild projective
    transformation T; ORB measures tie points between the image and its copy, and the
    residuals ``T(p) − p'`` of the correct matches (within the RANSAC bound ``THRESHOLD``) are measurement error only —
    no relief, no lens: the precision the real residuals are to be judged against.
    """
    rng = np.random.default_rng(seed)
    H, W = image.shape
    T = pl.ProjectiveTransform(float(rng.uniform(-20, 20)), 1.0 + float(rng.uniform(-.03, .03)),
                               float(rng.uniform(-.03, .03)), float(rng.uniform(-20, 20)),
                               float(rng.uniform(-.03, .03)), 1.0 + float(rng.uniform(-.03, .03)),
                               float(rng.uniform(-2e-5, 2e-5)), float(rng.uniform(-2e-5, 2e-5)))
    inv = T.inverse
    # the copy: pixel p' of the copy shows the image at T⁻¹(p')
    copy = rectify_image(image, lambda XY: inv(np.stack([XY[:, 0], -XY[:, 1]], -1)),
                                    (H, W), origin=(0.0, 0.0), pixel_size=1.0)
    copy = np.clip(np.round(copy), 0, 255).astype(np.uint8)
    p, q = measure_tie_points(image, copy, n_features)
    v = T(p) - q
    ok = np.hypot(v[:, 0], v[:, 1]) < THRESHOLD
    v = v[ok]
    sigma = float(np.sqrt(np.sum(v**2) / (2 * len(v))))
    return sigma, int(ok.sum())


@lru_cache(maxsize=2)
def mosaic_block(indices=AERIAL, model: str = "projective", factor: int = DOWNSAMPLE):
    """Tie points, pair fits, chained transforms and residuals of the chosen aerial images.

    Returns a dict: ``images``, ``ties`` (i, j, p_i, p_j) of every overlapping pair (inliers
    of its own fit), ``fits`` of the consecutive pairs (k → k − 1), ``transforms`` (k → 0),
    ``residuals`` (:func:`photolib.image_mosaic.tie_point_residuals`).
    """
    images = aerial_images(indices, factor)
    feats = [orb_features(img) for img in images]          # detected once per image
    fits, ties = [], []
    for k in range(1, len(images)):
        p_prev, p_k = match_features(feats[k - 1], feats[k])
        fit = im.fit_pair(p_k, p_prev, model=model, threshold=THRESHOLD, rng=k)
        fits.append(fit)
        ties.append((k - 1, k, p_prev[fit.inliers], p_k[fit.inliers]))
    transforms = im.chain_transforms([f.transform for f in fits])
    for i in range(len(images)):
        for j in range(i + 2, len(images)):
            pi, pj = match_features(feats[i], feats[j])
            if len(pi) < 20:
                continue
            fit = im.fit_pair(pj, pi, model=model, threshold=THRESHOLD, rng=10 * i + j)
            if fit.inliers.sum() >= 20:
                ties.append((i, j, pi[fit.inliers], pj[fit.inliers]))
    return {"images": images, "fits": fits, "ties": ties, "transforms": transforms,
            "residuals": im.tie_point_residuals(transforms, ties)}


def opencv_homography(p_src, p_dst, threshold: float = THRESHOLD):
    """``cv2.findHomography`` (RANSAC) on the same tie points: 3 × 3 matrix and inlier mask."""
    cv2 = _cv2()
    H, mask = cv2.findHomography(p_src.astype(np.float32), p_dst.astype(np.float32),
                                 cv2.RANSAC, threshold)
    return H / H[2, 2], mask.ravel().astype(bool)


def residual_rows(block) -> list[str]:
    """Printable table of the tie-point residuals (px of the reduced reference image)."""
    rows = [f"{'pair':>6s} {'n':>5s} {'RMS |v| px':>11s} {'max |v| px':>11s}  fitted?"]
    fitted = {(f_i, f_i + 1) for f_i in range(len(block["fits"]))}
    for r in block["residuals"]:
        rows.append(f"{r['i'] + 1:>2d}–{r['j'] + 1:<3d} {len(r['v']):5d} {r['rms']:11.2f} "
                    f"{r['max']:11.2f}  {'yes' if (r['i'], r['j']) in fitted else 'no (chain)'}")
    return rows


def plot_real_mosaic(mos, *, ax=None, seams=True, title="mosaic"):
    """The mosaic with its seam lines (nearest-centre partition) and image centres."""
    import matplotlib.pyplot as plt
    if ax is None:
        fig, ax = plt.subplots(figsize=(8, 6))
    else:
        fig = ax.figure
    ax.imshow(np.where(np.isfinite(mos.mosaic), mos.mosaic, 255), cmap="gray", extent=mos.extent,
              vmin=0, vmax=255, interpolation="nearest")
    if seams:
        src = mos.source.astype(float)
        ax.contour(src, levels=np.arange(-0.5, src.max() + 1), colors="tab:orange",
                   linewidths=1.0, extent=(mos.extent[0], mos.extent[1], mos.extent[3],
                                           mos.extent[2]), origin="upper")
    ax.plot(*mos.centres.T, "+", color="tab:red", ms=10)
    for k, c in enumerate(mos.centres):
        ax.annotate(str(k + 1), c, color="tab:red", xytext=(4, 4), textcoords="offset points")
    ax.set_xlabel("X = col of image 1 (px)")
    ax.set_ylabel("Y = −row of image 1 (px)")
    ax.set_title(title)
    ax.set_aspect("equal")
    return fig


def plot_tie_residuals(mos, block, scale: float = 30.0, per_pair: int = 40, ax=None):
    """Residual vectors T_i(p_i) − T_j(p_j), ``scale`` times enlarged, ``per_pair`` per pair.

    Every k-th tie point of each pair is drawn (k chosen for about ``per_pair`` arrows), so
    that the vectors stay readable; the table holds the statistics of all of them.
    """
    fig = plot_real_mosaic(mos, ax=ax, seams=True,
                           title=f"tie-point residuals (× {scale:g}); orange: seam lines")
    ax = fig.axes[0]
    colours = ("tab:blue", "tab:green", "tab:purple", "tab:cyan", "tab:pink", "tab:olive")
    for k, r in enumerate(block["residuals"]):
        step = max(1, len(r["v"]) // per_pair)
        at = im.plane_from_pixel(r["at"][::step])
        v = r["v"][::step] * np.array([1.0, -1.0])
        ax.quiver(at[:, 0], at[:, 1], v[:, 0], v[:, 1], angles="xy", scale_units="xy",
                  scale=1.0 / scale, width=0.002, color=colours[k % len(colours)],
                  label=f"{r['i'] + 1}–{r['j'] + 1}")
    ax.legend(loc="lower right", fontsize=8)
    return fig


class MosaicZoom(Explorer):
    """Zoom into the mosaic: a window of the mosaic beside the image each pixel comes from.

    Sliders move the window centre (X, Y in px of image 1) and its half size; across a seam
    line the right panel changes colour and the left one shows how the images join.
    """

    title = "mosaic zoom"

    def __init__(self, mos=None, half: int = 60):
        if mos is None:                      # the chapter's block at half the resolution
            block = mosaic_block()
            mos = im.image_mosaic(block["images"], block["transforms"], pixel_size=2.0)
        self.mos = mos
        ext = mos.extent
        cx, cy = (float(np.round(v / 5.0) * 5.0) for v in mos.centres[:2].mean(axis=0))
        self.controls = {"X": slider("X [px]", cx, float(np.ceil(ext[0])), float(np.floor(ext[1])),
                                     5, fmt=".0f"),
                         "Y": slider("Y [px]", cy, float(np.ceil(ext[2])), float(np.floor(ext[3])),
                                     5, fmt=".0f"),
                         "half": slider("half size [px]", float(half), 15, 200, 5, fmt=".0f")}
        self.live = LiveFigure((8.0, 3.8))
        ax, ax2 = self.live.figure.subplots(1, 2)
        self._img = ax.imshow(np.zeros((2, 2)), cmap="gray", vmin=0, vmax=255,
                              interpolation="nearest")
        self._src = ax2.imshow(np.zeros((2, 2)), cmap="tab10", vmin=0, vmax=9,
                               interpolation="nearest")
        ax.set_title("mosaic (zoom)")
        ax2.set_title("source image (colour)")
        for a in (ax, ax2):
            a.grid(False)
        for a in (self._img, self._src):
            self.live.animate(a)
        self._finish()

    def window(self, X, Y, half):
        """Row and column slices of the mosaic around (X, Y)."""
        c, r = self.mos.pixel(np.array([X, Y], float))
        h = int(half / self.mos.pixel_size)
        rows, cols = self.mos.mosaic.shape
        r0, c0 = min(max(int(r) - h, 0), rows - 1), min(max(int(c) - h, 0), cols - 1)
        return slice(r0, max(min(int(r) + h, rows), r0 + 1)), slice(c0, max(min(int(c) + h, cols), c0 + 1))

    def draw(self, X, Y, half) -> str:
        rs, cs = self.window(X, Y, half)
        m = self.mos.mosaic[rs, cs]
        ext = (cs.start - 0.5, cs.stop - 0.5, rs.stop - 0.5, rs.start - 0.5)
        self._img.set_data(np.where(np.isfinite(m), m, 255))
        self._img.set_extent(ext)
        s = self.mos.source[rs, cs]
        self._src.set_data(np.ma.masked_less(s, 0))
        self._src.set_extent(ext)
        for a in self.live.figure.axes:
            a.set_xlim(ext[0], ext[1])
            a.set_ylim(ext[2], ext[3])
        used = sorted(int(k) + 1 for k in np.unique(s) if k >= 0)
        return (f"window {m.shape[1]} × {m.shape[0]} px at X = {X:.0f}, Y = {Y:.0f}<br>"
                f"from image(s): {', '.join(map(str, used)) or 'none'}")


# -- structure from motion in outline (a simulated sequence) --------------------------------------
#: simulated camera: 640 × 426 px (the campus views' format), c = 600 px, σ = 0.5 px
SFM_CAMERA = {"width": 640, "height": 426, "c_px": 600.0, "sigma_px": 0.5}


def sfm_scene(n_images: int = 5, seed: int = 12, outliers: float = 0.1):
    """A simulated walk past an L-shaped building: true poses, points and tie points.

    Points on two façades (20 m × 10 m, 12 m × 10 m) and in the trees and bushes in front
    (up to 6 m high: a scene of depth, not of planes, which would leave the eight-point
    essential matrix undetermined); ``n_images``
    cameras on an arc 18–25 m away, turning to keep the corner in view. Image points have
    Gaussian noise σ = 0.5 px; in each consecutive pair ``outliers`` of the tie points are
    mismatched (paired with a random other point), as feature matching does.
    """
    rng = np.random.default_rng(seed)
    n = 260
    u = rng.uniform(0, 1, n)
    wall = rng.integers(0, 3, n)
    X = np.where(wall[:, None] == 0, np.column_stack([20 * u, np.zeros(n), rng.uniform(0, 10, n)]),
                 np.where(wall[:, None] == 1,
                          np.column_stack([np.zeros(n), 12 * u, rng.uniform(0, 10, n)]),
                          np.column_stack([rng.uniform(1, 20, n), -rng.uniform(1, 10, n),
                                           rng.uniform(0, 6, n)])))
    target = np.array([6.0, 3.0, 4.0])
    poses = []
    for k, a in enumerate(np.linspace(-0.35, 0.25, n_images)):
        X0 = target + np.array([22 * np.sin(a + 0.6), -22 * np.cos(a + 0.6), -2.4 + 0.3 * k])
        look = target - X0
        z = -look / np.linalg.norm(look)                     # camera looks along −z
        x = np.cross([0.0, 0.0, 1.0], z)
        x /= np.linalg.norm(x)
        R = np.column_stack([x, np.cross(z, x), z])
        poses.append((X0, R))
    cam = SFM_CAMERA
    half = np.array([(cam["width"] - 1) / 2, (cam["height"] - 1) / 2])
    xy, seen = [], []
    for X0, R in poses:
        p = pl.project(X, X0, R, cam["c_px"])
        xy.append(p + rng.normal(0, cam["sigma_px"], p.shape))
        seen.append(np.all(np.abs(p) < half, axis=1))
    pairs = []
    for k in range(n_images - 1):
        ids = np.flatnonzero(seen[k] & seen[k + 1])
        other = ids.copy()
        bad = rng.uniform(size=len(ids)) < outliers
        other[bad] = rng.permutation(ids)[: bad.sum()]
        pairs.append((ids, other, bad & (other != ids)))
    return {"X": X, "poses": poses, "xy": np.array(xy), "seen": np.array(seen), "pairs": pairs}


def sfm_pipeline(scene=None, threshold_px: float = 1.5):
    """Pairwise orientation → chaining → free bundle adjustment of :func:`sfm_scene`.

    Returns a dict with the pair orientations, the chained start poses, the bundle result,
    the similarity of the adjusted block to the truth (:func:`photolib.absolute_orientation`)
    and the differences of points and centres after it (in m).
    """
    from photolib import sfm
    sc = sfm_scene() if scene is None else scene
    c = SFM_CAMERA["c_px"]
    xy = sc["xy"]
    rel, orients = [], []
    for k, (ids, other, _) in enumerate(sc["pairs"]):
        po = sfm.orient_pair(xy[k, ids], xy[k + 1, other], c, threshold=threshold_px, rng=k)
        orients.append(po)
        rel.append((po.R2, po.base))
    # scales: base 0 has length 1; base k from the points pair k shares with pair k − 1
    scales, poses = [1.0], sfm.chain_poses(rel[:1], [1.0])
    for k in range(1, len(rel)):
        ids0, oth0, _ = sc["pairs"][k - 1]
        ids1, oth1, _ = sc["pairs"][k]
        good0 = ids0[orients[k - 1].inliers & (ids0 == oth0)]
        good1 = ids1[orients[k].inliers]
        common = np.intersect1d(good0, good1)
        (Xa, Ra), (Xb, Rb) = poses[k - 1], poses[k]
        Pg, _, _ = sfm.triangulate_midpoint(Xa, sfm.image_vectors(xy[k - 1, common], c) @ Ra.T,
                                            Xb, sfm.image_vectors(xy[k, common], c) @ Rb.T)
        _, l1, _ = sfm.triangulate_midpoint(np.zeros(3), sfm.image_vectors(xy[k, common], c),
                                            rel[k][1], sfm.image_vectors(xy[k + 1, common], c)
                                            @ rel[k][0].T)
        local = l1 * np.linalg.norm(sfm.image_vectors(xy[k, common], c), axis=1)
        scales.append(float(np.median(np.linalg.norm(Pg - Xb, axis=1) / local)))
        poses = sfm.chain_poses(rel[: k + 1], scales)
    # observations: every inlier tie point of every pair (a point's track = its id)
    obs = {}
    for k, (ids, other, _) in enumerate(sc["pairs"]):
        keep = orients[k].inliers & (ids == other)      # a mismatch that RANSAC kept is dropped
        for i in ids[keep]:
            obs[(k, int(i))] = xy[k, i]
            obs[(k + 1, int(i))] = xy[k + 1, i]
    keys = sorted(obs)
    img_idx = np.array([k for k, _ in keys])
    pt_ids = np.array(sorted({i for _, i in keys}))
    pt_idx = np.searchsorted(pt_ids, [i for _, i in keys])
    obs_xy = np.array([obs[k] for k in keys])
    start = np.empty((len(pt_ids), 3))
    for n, i in enumerate(pt_ids):
        ks = img_idx[pt_idx == n][:2]
        (Xa, Ra), (Xb, Rb) = poses[ks[0]], poses[ks[1]]
        start[n] = sfm.triangulate_midpoint(Xa, sfm.image_vectors(xy[ks[0], [i]], c) @ Ra.T,
                                            Xb, sfm.image_vectors(xy[ks[1], [i]], c) @ Rb.T)[0][0]
    ext = np.array([np.r_[X0, pl.opk_from_rotation(R)] for X0, R in poses])
    res = pl.bundle_adjustment(obs_xy, img_idx, pt_idx, ext, start, c, datum="free")
    sim = pl.absolute_orientation(res.points, sc["X"][pt_ids])
    dX = sim(res.points) - sc["X"][pt_ids]
    dC = sim(res.exterior[:, :3]) - np.array([X0 for X0, _ in sc["poses"]])
    n_bad = sum(int(p[2].sum()) for p in sc["pairs"])
    n_bad_kept = sum(int((o.inliers & p[2]).sum()) for o, p in zip(orients, sc["pairs"]))
    return {"scene": sc, "orients": orients, "start_poses": poses, "scales": scales,
            "bundle": res, "similarity": sim, "dX": dX, "dC": dC, "point_ids": pt_ids,
            "n_mismatched": n_bad, "n_mismatched_kept": n_bad_kept}


def plot_sfm(out):
    """Camera path and points: truth and the adjusted block (after the similarity)."""
    import matplotlib.pyplot as plt
    sc, res, sim = out["scene"], out["bundle"], out["similarity"]
    fig, ax = plt.subplots(figsize=(7, 5))
    ax.plot(*sc["X"][:, :2].T, ".", color="0.75", ms=3, label="true points")
    P = sim(res.points)
    ax.plot(*P[:, :2].T, ".", color="tab:blue", ms=3, label="adjusted points")
    C0 = np.array([X0 for X0, _ in sc["poses"]])
    C = sim(res.exterior[:, :3])
    ax.plot(*C0[:, :2].T, "o-", color="0.5", mfc="none", label="true camera path")
    ax.plot(*C[:, :2].T, "x-", color="tab:red", label="adjusted camera path")
    for k, (X0, R) in enumerate(sc["poses"]):
        d = -R[:, 2] * 4.0
        ax.annotate("", X0[:2] + d[:2], X0[:2], arrowprops={"arrowstyle": "->", "color": "0.4"})
        ax.annotate(str(k + 1), C[k, :2], xytext=(5, -12), textcoords="offset points")
    ax.set_aspect("equal")
    ax.set_xlabel("X (m)")
    ax.set_ylabel("Y (m)")
    ax.set_title("structure from motion: plan view (after a 7-parameter similarity to the truth)")
    ax.legend(fontsize=8, loc="upper left")
    return fig
