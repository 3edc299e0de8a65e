"""Reference geometry for the orthophoto tests: the slab test of a segment against a box."""

from __future__ import annotations

import numpy as np


def segment_hits_box(P, X0, box) -> bool:
    """Does the open segment P → X0 pass through the box below its roof?

    ``box = (Xmin, Xmax, Ymin, Ymax, height)``, standing on Z = 0: the independent
    visibility reference of the true-orthophoto tests (a per-axis slab intersection).
    """
    lo, hi = np.array([box[0], box[2], 0.0]), np.array([box[1], box[3], box[4]])
    d = np.asarray(X0, float) - P
    t0, t1 = 1e-9, 1.0
    for k in range(3):
        if abs(d[k]) < 1e-15:
            if not lo[k] <= P[k] <= hi[k]:
                return False
            continue
        a, b = (lo[k] - P[k]) / d[k], (hi[k] - P[k]) / d[k]
        t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
    return t1 - t0 > 1e-9
