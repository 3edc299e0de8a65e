"""Bundle adjustment of synthetic aerial blocks: photolib (with full statistics) against
Ceres, through pycolmap's bundle adjuster, each solver in its own process, one thread.

The blocks (``make_block``): strips of nadir-ish images (c = 50 mm, 120 × 120 mm format,
500 m above ground, 60 % forward and 30 % side overlap), object points scattered at random
over 0–30 m of relief and kept if seen in two images or more, image noise 3 µm, control
points: the nine points nearest a 3 × 3 grid over the block, fixed (the datum, the same in
both solvers). Initial values: exterior orientation off by N(0, 1 m) and N(0, 0.01 rad),
new points by N(0, 2 m). photolib's ``bundle_adjustment`` runs to its default tolerance and
computes σ0, every covariance block and the redundancy numbers; Ceres (pycolmap
``create_default_bundle_adjuster``, Levenberg–Marquardt, its automatic choice of the Schur
solver, focal length, principal point and distortion constant, ``num_threads = 1``) gets the
same observations in pixels (6 µm pixels, ``u = x'/ps + cx``, ``v = −y'/ps + cy``) and poses
from :func:`photolib.colmap_pose_from_exterior`; both must reach the same RMS of the image
residuals to 9 significant digits.

Every solve runs in a fresh child process (``python -m benchmarks.bench_bundle --child``,
``OPENBLAS_NUM_THREADS=1``); the child reports its solve time (best of ``REPEAT`` solves
in that process, the block built once, CPU time of the process: on a shared machine the
wall-clock time, also printed, measures the other users) and its peak RSS (``resource.getrusage`` of the
child, block and imports included). Targets (``TARGETS``):

* photolib with statistics at most 2.5× Ceres at 49, 100 and 200 images;
* from 50 to 400 images, photolib's time and peak memory per observation grow by at most
  ``LINEAR_SLACK`` (time and memory no faster than linear in the observations);
* photolib's peak memory at 200 images under 1 GiB.

The scaling blocks run in ``ROUNDS`` interleaved rounds of fresh children (least CPU time,
largest peak of the rounds per block): the per-observation ratio of two single runs moved
by ±15 % on an idle 2-core machine, more than the 1.25 it is compared with.

pycolmap is a benchmark-only dependency (``pip install -c constraints.txt '.[bench]'``);
without it the comparison is skipped (said so) and only the scaling table is measured.

Run: ``.venv/bin/python -m benchmarks bench_bundle`` (or ``-m benchmarks.bench_bundle``
with ``--images 49 100 200 --scaling 50 100 200 400``).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np

#: most photolib/Ceres time ratio, largest photolib peak RSS at 200 images (bytes)
TARGETS = {"ratio": 2.5, "memory_200": 1 << 30}
#: the block sizes (images) at which the ratio target applies (others: reported)
RATIO_AT = (49, 100, 200)
#: per-observation time or memory at 400 images may exceed that at 50 by this factor
LINEAR_SLACK = 1.25
REPEAT = 3
#: interleaved rounds of the scaling run (see ``_scaling_rows``)
ROUNDS = 3
C_MM, PIXEL_MM, HALF_FORMAT_MM, HEIGHT_M = 50.0, 0.006, 60.0, 500.0
#: (strips, images per strip) for a number of images
SHAPES = {10: (2, 5), 49: (7, 7), 50: (5, 10), 100: (10, 10), 200: (10, 20), 400: (20, 20)}


def _rot(o, p, k):
    """R = R_ω·R_φ·R_κ (written out, independent of photolib)."""
    co, so, cp, sp_, ck, sk = np.cos(o), np.sin(o), np.cos(p), np.sin(p), np.cos(k), np.sin(k)
    Ro = np.array([[1, 0, 0], [0, co, -so], [0, so, co]])
    Rp = np.array([[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]])
    Rk = np.array([[ck, -sk, 0], [sk, ck, 0], [0, 0, 1]])
    return Ro @ Rp @ Rk


def make_block(n_images: int, seed: int = 0, obs_per_image: float = 620.0) -> dict:
    """A synthetic aerial block of ``n_images`` images (a key of ``SHAPES``); see the module."""
    strips, per = SHAPES[n_images]
    rng = np.random.default_rng(seed)
    foot = 2 * HALF_FORMAT_MM / C_MM * HEIGHT_M  # ground footprint, m
    base, gap = 0.4 * foot, 0.7 * foot
    ext = np.array([[k * base, s * gap, HEIGHT_M + rng.normal(0, 5),
                     *np.radians(rng.normal(0, 1, 3))] for s in range(strips) for k in range(per)])
    lo = np.array([-foot / 2, -foot / 2])
    hi = np.array([(per - 1) * base + foot / 2, (strips - 1) * gap + foot / 2])
    n_pts = int(obs_per_image / foot**2 * np.prod(hi - lo) * 1.0)
    P = np.column_stack([rng.uniform(lo, hi, (n_pts, 2)), rng.uniform(0, 30, n_pts)])
    xy, ji, pi = [], [], []
    for j, e in enumerate(ext):
        k = (P - e[:3]) @ _rot(*e[3:])
        p = np.column_stack([-C_MM * k[:, 0] / k[:, 2], -C_MM * k[:, 1] / k[:, 2]])
        ok = np.flatnonzero(np.all(np.abs(p) < HALF_FORMAT_MM, axis=1))
        xy.append(p[ok])
        ji.append(np.full(len(ok), j))
        pi.append(ok)
    xy, ji, pi = np.vstack(xy), np.concatenate(ji), np.concatenate(pi)
    keep = np.bincount(pi, minlength=n_pts) >= 2
    new = np.cumsum(keep) - 1
    sel = keep[pi]
    xy, ji, pi, P = xy[sel], ji[sel], new[pi[sel]], P[keep]
    xy = xy + rng.normal(0, 0.003, xy.shape)
    grid = [lo + (hi - lo) * np.array([a, b]) for a in (0.05, 0.5, 0.95) for b in (0.05, 0.5, 0.95)]
    control = sorted({int(np.argmin(np.linalg.norm(P[:, :2] - g, axis=1))) for g in grid})
    P0 = P.copy()
    free = np.setdiff1d(np.arange(len(P)), control)
    P0[free] += rng.normal(0, 2.0, (len(free), 3))
    ext0 = ext + np.column_stack([rng.normal(0, 1.0, (len(ext), 3)),
                                  rng.normal(0, 0.01, (len(ext), 3))])
    return dict(xy=xy, ji=ji, pi=pi, ext0=ext0, P0=P0, control=np.array(control), ext=ext, P=P)


def _rms(b, ext, P):
    """RMS of the image residuals (mm) of exterior orientations ``ext`` and points ``P``."""
    out = np.empty_like(b["xy"])
    for j in range(len(ext)):
        m = b["ji"] == j
        k = (P[b["pi"][m]] - ext[j, :3]) @ _rot(*ext[j, 3:])
        out[m] = np.column_stack([-C_MM * k[:, 0] / k[:, 2], -C_MM * k[:, 1] / k[:, 2]])
    return float(np.sqrt(np.mean((out - b["xy"]) ** 2)))


def _solve_photolib(b):
    import photolib as pl

    res = pl.bundle_adjustment(b["xy"], b["ji"], b["pi"], b["ext0"], b["P0"], C_MM,
                               control=b["control"])
    assert res.converged and np.all(np.isfinite(res.redundancy_numbers))
    assert abs(res.redundancy_numbers.sum() - res.redundancy) < 1e-6 * res.redundancy
    return res.exterior, res.points, f"{res.iterations} it"


def _ceres_problem(b):
    """A pycolmap Reconstruction of the block: one PINHOLE camera (px), a trivial rig and
    frame per image, the 3-D points with their tracks."""
    import pycolmap

    import photolib as pl

    f, half = C_MM / PIXEL_MM, HALF_FORMAT_MM / PIXEL_MM
    rec = pycolmap.Reconstruction()
    cam = pycolmap.Camera(model="PINHOLE", width=int(2 * half), height=int(2 * half),
                          params=[f, f, half, half], camera_id=1)
    rec.add_camera_with_trivial_rig(cam)
    ji, pi = b["ji"], b["pi"]
    uv = np.column_stack([b["xy"][:, 0] / PIXEL_MM + half, -b["xy"][:, 1] / PIXEL_MM + half])
    order = np.argsort(ji, kind="stable")
    starts = np.searchsorted(ji[order], np.arange(len(b["ext0"]) + 1))
    index_in_image = np.empty(len(ji), int)
    for j in range(len(b["ext0"])):
        rows = order[starts[j]:starts[j + 1]]
        index_in_image[rows] = np.arange(len(rows))
        q, t = pl.colmap_pose_from_exterior(b["ext0"][j, :3], _rot(*b["ext0"][j, 3:]))
        image = pycolmap.Image(name=f"{j}", keypoints=uv[rows], camera_id=1, image_id=j + 1)
        pose = pycolmap.Rigid3d(pycolmap.Rotation3d(np.r_[q[1:], q[0]]), t)  # xyzw
        rec.add_image_with_trivial_frame(image, pose)
    by_point = np.argsort(pi, kind="stable")
    pstarts = np.searchsorted(pi[by_point], np.arange(len(b["P0"]) + 1))
    ids = []
    for p in range(len(b["P0"])):
        rows = by_point[pstarts[p]:pstarts[p + 1]]
        track = pycolmap.Track([pycolmap.TrackElement(int(ji[r]) + 1, int(index_in_image[r]))
                                for r in rows])
        ids.append(rec.add_point3D(b["P0"][p], track))
    return rec, ids


def _solve_ceres(b, state):
    import pycolmap

    import photolib as pl

    rec, ids = _ceres_problem(b) if state is None else state
    opts = pycolmap.BundleAdjustmentOptions(refine_focal_length=False,
                                            refine_principal_point=False,
                                            refine_extra_params=False, print_summary=False)
    opts.ceres.solver_options.num_threads = 1
    opts.ceres.solver_options.function_tolerance = 1e-12
    opts.ceres.solver_options.gradient_tolerance = 1e-12
    opts.ceres.solver_options.parameter_tolerance = 1e-12
    config = pycolmap.BundleAdjustmentConfig()
    for j in range(len(b["ext0"])):
        config.add_image(j + 1)
    for p in b["control"]:
        config.add_constant_point(ids[int(p)])
    summary = pycolmap.create_default_bundle_adjuster(opts, config, rec).solve()
    ext = np.empty_like(b["ext0"])
    for j in range(len(ext)):
        pose = rec.image(j + 1).cam_from_world()
        xyzw = pose.rotation.quat
        X0, R = pl.exterior_from_colmap_pose(np.r_[xyzw[3], xyzw[:3]], pose.translation)
        ext[j] = np.r_[X0, pl.opk_from_rotation(R)]
    P = np.array([rec.point3D(i).xyz for i in ids])
    cs = summary.ceres_summary
    return ext, P, f"{cs.num_successful_steps + cs.num_unsuccessful_steps} it"


def _stage_clock():
    """CPU seconds spent in photolib's iterations, in its statistics stage and, within the
    statistics, in the blocks of K⁻¹ and the covariances (wrappers around the stage
    functions of ``photolib.bundle._adjustment``; their overhead is a few calls per solve)."""
    import photolib.bundle._adjustment as ad

    spent = {"iterate": 0.0, "statistics": 0.0, "inverse+covariances": 0.0}

    def timed(fn, key):
        def run(*args, **kw):
            t = time.process_time()
            try:
                return fn(*args, **kw)
            finally:
                spent[key] += time.process_time() - t
        return run

    ad._iterate = timed(ad._iterate, "iterate")
    ad._statistics = timed(ad._statistics, "statistics")
    ad.covariances = timed(ad.covariances, "inverse+covariances")
    inverse_blocks = ad.ReducedSystem.inverse_blocks
    ad.ReducedSystem.inverse_blocks = lambda self, *a: timed(
        inverse_blocks, "inverse+covariances")(self, *a)
    return spent


def child(solver: str, n_images: int, repeat: int = REPEAT) -> dict:
    """One solver on one block in this process: best solve time (s), peak RSS (bytes),
    RMS (mm); for photolib also the statistics stage and its inverse + covariances work in
    units of one iteration (of the best solve)."""
    b = make_block(n_images)
    warm = make_block(10, seed=1)  # imports and first calls, untimed
    _solve_ceres(warm, None) if solver == "ceres" else _solve_photolib(warm)
    del warm
    spent = _stage_clock() if solver == "photolib" else None
    stages = {}
    wall, cpu = [], []
    for _ in range(repeat):
        # BA changes the reconstruction: a fresh one each time, built outside the timing
        state = _ceres_problem(b) if solver == "ceres" else None
        t, c = time.perf_counter(), time.process_time()
        if spent is not None:
            spent.update(dict.fromkeys(spent, 0.0))
        ext, P, note = _solve_ceres(b, state) if solver == "ceres" else _solve_photolib(b)
        wall.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
        if spent is not None and cpu[-1] == min(cpu):
            per_iteration = spent["iterate"] / int(note.split()[0])
            stages = {"statistics_it": spent["statistics"] / per_iteration,
                      "extra_it": spent["inverse+covariances"] / per_iteration}
        del state
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    return dict(solver=solver, images=n_images, points=len(b["P0"]), observations=len(b["xy"]),
                time=min(cpu), wall=min(wall), peak=peak, rms=_rms(b, ext, P), note=note,
                **stages)


def _run_child(solver, n_images, repeat=REPEAT):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-m", "benchmarks.bench_bundle", "--child", solver,
                          "--images", str(n_images), "--repeat", str(repeat)],
                         capture_output=True, text=True, env=env, check=False)
    if out.returncode:
        raise RuntimeError(f"{solver} child ({n_images} images) failed:\n{out.stderr[-3000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def _mib(b):
    return f"{b / 2**20:7.0f} MiB"


def _scaling_rows(scaling, repeat=REPEAT, rounds=ROUNDS):
    """photolib on every block of ``scaling``, in ``rounds`` interleaved rounds (50, 100, …,
    400, then again), each a fresh child: per block the round with the least CPU time and the
    largest peak RSS of all rounds. A quiet or busy spell of a shared machine then falls on
    every block size alike, not on the one whose child happened to run in it."""
    best = {}
    for _ in range(rounds):
        for n in scaling:
            row = _run_child("photolib", n, repeat)
            old = best.get(n)
            if old is not None:
                row["peak"] = max(row["peak"], old["peak"])
                if old["time"] <= row["time"]:
                    row = dict(old, peak=row["peak"])
            best[n] = row
    return [best[n] for n in scaling]


def run(images=(49, 100, 200), scaling=(50, 100, 200, 400), repeat=REPEAT) -> int:
    print(f"load {os.getloadavg()[0]:.2f} (1 min) on {os.cpu_count()} cores; one thread per "
          "solver, each in its own process", flush=True)
    missed = []
    if importlib.util.find_spec("pycolmap") is None:
        print("pycolmap is not installed: the comparison with Ceres is SKIPPED "
              "(pip install -c constraints.txt '.[bench]')", flush=True)
    else:
        print(f"{'images':>6} {'points':>7} {'obs':>7} | {'photolib':>9} {'peak':>11} | "
              f"{'Ceres':>8} {'peak':>11} | ratio | RMS photolib / Ceres (mm)", flush=True)
        for n in images:
            ours, ref = _run_child("photolib", n, repeat), _run_child("ceres", n, repeat)
            digits = -np.log10(abs(ours["rms"] - ref["rms"]) / ours["rms"] + 1e-17)
            ratio = ours["time"] / ref["time"]
            ok = ratio <= TARGETS["ratio"] or n not in RATIO_AT
            missed += [] if ok else [f"ratio at {n} images"]
            print(f"{n:6d} {ours['points']:7d} {ours['observations']:7d} | {ours['time']:8.2f}s "
                  f"{_mib(ours['peak'])} | {ref['time']:7.2f}s {_mib(ref['peak'])} | "
                  f"{ratio:4.2f}× {'      ' if ok else 'MISSED'} | {ours['rms']:.10g} / "
                  f"{ref['rms']:.10g} ({digits:.1f} digits; {ours['note']}, {ref['note']})",
                  flush=True)
            if digits < 9:
                missed.append(f"same optimum at {n} images")
    rows = _scaling_rows(scaling, repeat)
    print(f"\nphotolib scaling (target: per-observation time and memory at {scaling[-1]} images "
          f"≤ {LINEAR_SLACK}× those at {scaling[0]})")
    print(f"{'images':>6} {'obs':>7} | {'time':>7} {'µs/obs':>7} | {'peak':>11} {'KiB/obs':>8} | "
          "statistics in iterations: whole stage / K⁻¹ blocks + covariances (the "
          "normal equations at the estimate are those of the last iteration)")
    for row in rows:
        print(f"{row['images']:6d} {row['observations']:7d} | {row['time']:6.2f}s "
              f"{row['time'] / row['observations'] * 1e6:7.1f} | {_mib(row['peak'])} "
              f"{row['peak'] / row['observations'] / 1024:8.2f} | "
              f"{row['statistics_it']:.2f} / {row['extra_it']:.2f}")
    first, last = rows[0], rows[-1]
    for key in ("time", "peak"):
        growth = (last[key] / last["observations"]) / (first[key] / first["observations"])
        print(f"{key} per observation, {last['images']} vs {first['images']} images: "
              f"{growth:.2f}×")
        if growth > LINEAR_SLACK:
            missed.append(f"linear {key}")
    for row in rows:
        if row["images"] == 200 and row["peak"] >= TARGETS["memory_200"]:
            missed.append("memory at 200 images")
    print("all targets met" if not missed else f"missed: {', '.join(missed)}")
    return 1 if missed else 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--child", choices=("photolib", "ceres"))
    ap.add_argument("--images", type=int, nargs="*", default=[49, 100, 200])
    ap.add_argument("--scaling", type=int, nargs="*", default=[50, 100, 200, 400])
    ap.add_argument("--repeat", type=int, default=REPEAT)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(child(args.child, args.images[0], args.repeat)))
        return 0
    return run(tuple(args.images), tuple(args.scaling), args.repeat)


if __name__ == "__main__":
    sys.exit(main())
