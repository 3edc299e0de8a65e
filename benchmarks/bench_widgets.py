"""Widget redraw time: every chapter widget, one slider move → figure PNG and text.

Target: at most 50 ms per update (the sliders update live, ``continuous_update=True``).
Each update runs the full callback: the numbers (``*_report``), moving the artists,
blitting on the cached background and encoding the PNG that the Output widget shows.
"""

from __future__ import annotations

import itertools
import sys

from benchmarks._timing import best_time

TARGET_MS = 50.0


def _cases():
    from photolib.nb import (bundle, distortion, glossary, intro, measurement, optics, plane,
                             products, project, projection, resection, rotations, sensors,
                             stereo)

    return [
        (rotations.RotationExplorer, "phi", (10.0, 60.0)),
        (rotations.OrderExplorer, "omega", (30.0, 70.0)),
        (distortion.DistortionExplorer, "A1", (-2.0, 4.0)),
        (distortion.IterationExplorer, "A1", (-2.0, -60.0)),
        (projection.ProjectionExplorer, "kappa", (0.0, 25.0)),
        (projection.FootprintExplorer, "phi", (0.0, 20.0)),
        # 200 m ↔ 1500 m changes the scale every time: the full-redraw path of a rescale
        (projection.FootprintExplorer, "Z0", (200.0, 1500.0)),
        (plane.ProjectiveExplorer, "c1", (0.15, 0.35)),
        (plane.RectificationExplorer, "dcol", (2.0, 8.0)),
        (resection.ResectionExplorer, "noise_um", (5.0, 20.0)),
        (resection.DLTExplorer, "depth", (1.0, 6.0)),
        (stereo.StereoPairExplorer, "B", (10.0, 50.0)),
        (stereo.EpipolarExplorer, "x1", (-10.0, 10.0)),
        (bundle.BlockExplorer, "n_control", (4.0, 8.0)),
        (bundle.BlunderExplorer, "blunder_um", (20.0, 60.0)),
        (bundle.PrecisionExplorer, "noise_um", (2.0, 6.0)),
        (optics.ThinLensExplorer, "a", (100.0, 300.0)),
        (optics.DepthOfFieldExplorer, "k", (2.8, 11.0)),
        (optics.AiryExplorer, "k", (4.0, 11.0)),
        (measurement.LoGExplorer, "sigma", (1.0, 3.5)),
        (measurement.ThresholdExplorer, "radius", (3.0, 10.0)),
        (measurement.EllipseExplorer, "arc_deg", (60.0, 360.0)),
        (measurement.LSMExplorer, "offset", (0.5, 3.0)),
        (products.ReliefExplorer, "h", (10.0, 50.0)),
        (products.OrthoErrorExplorer, "amplitude", (0.5, 2.0)),
        (products.TrueOrthoExplorer, "height", (10.0, 40.0)),
        (glossary.GlossaryExplorer, "query", ("ortho", "kalibr")),
        (sensors.QuantisationExplorer, "bits", (2.0, 7.0)),
        (sensors.AliasingExplorer, "frequency", (70.0, 150.0)),
        (sensors.BayerExplorer, "period_px", (3.0, 9.0)),
        (intro.ImageScaleExplorer, "log_distance", (1.0, 3.5)),
        (intro.FlightBlockExplorer, "height_m", (900.0, 2500.0)),
        (project.ChainExplorer, "view_a", (0.0, 13.0)),
        (project.NoiseExplorer, "sigma", (0.5, 1.5)),
    ]


def run() -> int:
    worst = 0.0
    for cls, name, values in _cases():
        explorer = cls()
        cycle = itertools.cycle(values)
        slider = explorer.controls[name]

        def move(slider=slider, cycle=cycle):
            slider.value = next(cycle)  # the observe callback redraws

        ms = best_time(move, repeat=5, min_time=0.2) * 1000.0
        worst = max(worst, ms)
        print(f"{cls.__name__:22s} slider {name:6s} {ms:6.1f} ms per update")
    verdict = "OK" if worst <= TARGET_MS else "TOO SLOW"
    print(f"slowest widget: {worst:.1f} ms per update (target ≤ {TARGET_MS:.0f} ms): {verdict}")
    return 0 if worst <= TARGET_MS else 1


if __name__ == "__main__":
    sys.exit(run())
