"""What a student sees of every widget, measured without a browser (issue 14, point 7).

The PNG's pixels against its CSS size (sharp on a HiDPI screen), slider tracks against their
range (every value reachable with the mouse), label columns against their text (nothing
truncated), and with matplotlib's renderer: texts inside the figure, 3-D tick labels apart,
legends off the data, the relief displacement large enough to see. ``tests/browser`` checks
the same in Chromium. SymPy results in the committed chapters are LaTeX.
"""

from __future__ import annotations

import base64
import io
import json
import re
from pathlib import Path

import ipywidgets as widgets
import numpy as np
import pytest
from PIL import Image

from .explorer_checks import (
    all_explorers,
    legend_covers,
    outside_figure,
    overlapping_ticks_3d,
    slider_values,
)

pytestmark = pytest.mark.usefixtures("close_figures")

REPO = Path(__file__).resolve().parents[1]
EXPLORERS = all_explorers()
IDS = [cls.__name__ for cls in EXPLORERS]
# a new explorer is found by all_explorers() and so checked below; this keeps the search honest
assert {"RotationExplorer", "ThresholdExplorer", "ProjectionExplorer", "ReliefExplorer"} <= set(IDS)

#: CSS pixels of an ipywidgets 8 slider that are neither label nor track: the readout (at
#: least 72 px, ``--jp-widgets-inline-width-tiny``) and its 4 px margin, the track's margins
#: (6 px each side), the label's margin, the widget's own margins
SLIDER_NOT_TRACK_PX = 100
#: the widgets' label font in JupyterLab, pixels (``--jp-widgets-font-size``)
LABEL_FONT_PX = 13
#: ipywidgets' label column when a control sets none (``--jp-widgets-inline-label-width``)
DEFAULT_LABEL_PX = 80


def _px(length) -> float:
    assert str(length).endswith("px"), f"not a length in px: {length!r}"
    return float(str(length)[:-2])


# -- sharp: 2 device pixels per CSS pixel ------------------------------------------------------

@pytest.mark.parametrize("cls", EXPLORERS, ids=IDS)
def test_widget_png_has_twice_its_css_width(cls):
    e = cls()
    output = e.live.output.outputs[0]
    image = Image.open(io.BytesIO(base64.b64decode(output["data"]["image/png"])))
    css = output["metadata"].get("image/png", {})
    assert "width" in css and "height" in css, f"{cls.__name__}: the PNG has no CSS size"
    # the CSS size is the figure's size at 80 px per inch: the layout the notebooks had
    w_in, h_in = e.live.figure.get_size_inches()
    assert (css["width"], css["height"]) == (round(80 * w_in), round(80 * h_in))
    assert image.width >= 2 * css["width"] and image.height >= 2 * css["height"], (
        f"{cls.__name__}: PNG {image.size} for CSS {css['width']}×{css['height']}")


def test_png_stays_sharp_after_a_slider_move():
    from photolib.nb import rotations

    e = rotations.RotationExplorer()
    e.controls["omega"].value = 45.0
    output = e.live.output.outputs[0]
    image = Image.open(io.BytesIO(base64.b64decode(output["data"]["image/png"])))
    assert image.width >= 2 * output["metadata"]["image/png"]["width"]


# -- controls: every value reachable, no label truncated ---------------------------------------

def _sliders(explorer):
    return {name: c for name, c in explorer.controls.items()
            if isinstance(c, (widgets.FloatSlider, widgets.IntSlider))}


@pytest.mark.parametrize("cls", EXPLORERS, ids=IDS)
def test_slider_track_has_a_pixel_per_step(cls):
    e = cls()
    for name, c in _sliders(e).items():
        track = _px(c.layout.width) - _px(c.style.description_width) - SLIDER_NOT_TRACK_PX
        steps = (c.max - c.min) / c.step
        assert track >= steps - 1e-6, (
            f"{cls.__name__}.{name}: {steps:.0f} steps on a track of about {track:.0f} px "
            f"({(c.max - c.min) / track:.2f} per pixel, step {c.step:g})")


def _text_width_px(text: str) -> float:
    """Width of ``text`` in DejaVu Sans at the widgets' 13 px, by matplotlib's Agg renderer."""
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.font_manager import FontProperties

    renderer = RendererAgg(10, 10, 72)  # 72 dpi: points are pixels
    w, _, _ = renderer.get_text_width_height_descent(
        text, FontProperties(family="DejaVu Sans", size=LABEL_FONT_PX), ismath=False)
    return w


def _labelled(controls):
    for name, c in controls.items():
        if getattr(c, "description", ""):
            width = getattr(c.style, "description_width", "") or f"{DEFAULT_LABEL_PX}px"
            yield name, c.description, _px(width)


def _glossary():
    from photolib.nb.glossary import GlossaryExplorer

    return GlossaryExplorer


@pytest.mark.parametrize("cls", [*EXPLORERS, _glossary()], ids=[*IDS, "GlossaryExplorer"])
def test_no_control_label_is_truncated(cls):
    e = cls()
    for name, text, width in _labelled(e.controls):
        need = _text_width_px(text) + 4.0
        assert width >= need, f"{cls.__name__}.{name}: {text!r} needs {need:.0f} px, has {width:g}"


def test_toggle_buttons_fit_their_names():
    from photolib.nb import plane

    e = plane.RectificationExplorer()
    buttons = e.controls["model"]
    width = _px(buttons.style.button_width)
    for name in buttons.options:
        # a button's text has 2 × 8 px of padding beside it
        assert width >= _text_width_px(name) + 16.0, (name, buttons.style.button_width)


# -- the figure: measured with matplotlib's renderer -------------------------------------------

@pytest.mark.parametrize("cls", EXPLORERS, ids=IDS)
def test_axis_labels_and_ticks_inside_the_figure(cls):
    e = cls()
    assert outside_figure(e.live.figure) == [], f"{cls.__name__}: cut off at the figure's edge"


def _probe(cls):
    axes = cls().live.figure.axes
    return any(hasattr(ax, "zaxis") for ax in axes), any(ax.get_legend() is not None for ax in axes)


_KINDS = {cls: _probe(cls) for cls in EXPLORERS}     # (3-D axes, a legend), built once
THREE_D = [cls for cls in EXPLORERS if _KINDS[cls][0]]
assert {"ProjectionExplorer", "RotationExplorer", "OrderExplorer", "DLTExplorer"} <= {
    c.__name__ for c in THREE_D}


@pytest.mark.parametrize("cls", THREE_D, ids=[c.__name__ for c in THREE_D])
def test_3d_tick_labels_do_not_overlap(cls):
    e = cls()
    assert overlapping_ticks_3d(e.live.figure) == []


def test_static_3d_figures_have_readable_ticks():
    import matplotlib.pyplot as plt

    from photolib.nb import projection, resection, rotations

    rep = projection.projection_report()
    figs = [projection.plot_projection(rep["X0"], rep["R"], 50.0),
            rotations.plot_frames([np.eye(3)], ["identity"]),
            resection.plot_scene(resection.control_points(), [])]
    try:
        for fig in figs:
            assert overlapping_ticks_3d(fig) == []
    finally:
        for fig in figs:
            plt.close(fig)


WITH_LEGEND = [cls for cls in EXPLORERS if _KINDS[cls][1]]
assert {"IterationExplorer", "EllipseExplorer", "DLTExplorer"} <= {c.__name__ for c in WITH_LEGEND}


@pytest.mark.parametrize("cls", WITH_LEGEND, ids=[c.__name__ for c in WITH_LEGEND])
def test_legend_covers_no_data(cls):
    e = cls()
    for name, c in _sliders(e).items():
        start = c.value
        for value in slider_values(c, 7):
            c.value = value
            covered = legend_covers(e.live.figure)
            assert covered == [], f"{cls.__name__}: {name} = {value:g}: legend over {covered}"
        c.value = start


# -- chapter 12: the relief displacement is a few mm on a 200 mm radius: zoomed ----------------

def _widest_foot_top_css_px(fig):
    """Largest distance, CSS px (80 per inch), between a blue and a red single point drawn in
    the same axes: the foot and the top of the tower in the image."""
    from matplotlib.colors import to_hex

    fig.canvas.draw()
    best = 0.0
    for ax in fig.axes:
        points = {}
        for line in ax.lines:
            xy = np.asarray(line.get_xydata(), dtype=float)
            if line.get_marker() == "o" and len(xy) == 1:
                points.setdefault(to_hex(line.get_color()), []).append(
                    line.get_transform().transform(xy)[0])
        for foot in points.get("#1f77b4", []):
            for top in points.get("#d62728", []):
                best = max(best, float(np.hypot(*(top - foot))) * 80.0 / fig.dpi)
    return best


@pytest.mark.parametrize("h", [5.0, 30.0])
def test_relief_displacement_is_visible_in_the_widget(h):
    from photolib.nb import products

    e = products.ReliefExplorer(h=h)
    assert e.report["dr"] < 3.0                      # a small effect: a few mm or less
    assert _widest_foot_top_css_px(e.live.figure) >= 60.0


def test_relief_displacement_is_visible_in_the_static_figure():
    import matplotlib.pyplot as plt

    from photolib.nb import products

    fig = products.plot_relief_geometry(30.0, 300.0, 120.0)
    try:
        assert _widest_foot_top_css_px(fig) >= 60.0
    finally:
        plt.close(fig)


def test_relief_zoom_rescales_both_ways():
    from photolib.nb import products

    e = products.ReliefExplorer(h=30.0)
    small = e._zoom.get_xlim()
    e.set(h=100.0, H=150.0, R=250.0)               # Δr = 167 mm: the zoom grows
    assert e._zoom.get_xlim()[1] > e.report["dr"] > small[1]
    e.set(h=1.0, H=600.0, R=10.0)                  # Δr < 0.01 mm: it shrinks again
    assert e._zoom.get_xlim()[1] <= 1.0


# -- SymPy results are LaTeX in the committed chapters -----------------------------------------

_SYMPY_TEXT = re.compile(r"Matrix\(|Eq\(|\b(sin|cos|tan|sqrt|atan2?)\(")
CHAPTERS = sorted(p for p in (REPO / "notebooks").glob("[01][0-9]-*.ipynb")
                  if not p.name.startswith("13-"))


@pytest.mark.parametrize("path", CHAPTERS, ids=[p.stem for p in CHAPTERS])
def test_sympy_results_are_rendered_as_latex(path):
    nb = json.loads(path.read_text(encoding="utf-8"))
    plain_only = []
    for i, cell in enumerate(nb["cells"]):
        for out in cell.get("outputs", []) if cell["cell_type"] == "code" else []:
            data = out.get("data", {})
            text = "".join(data.get("text/plain", ""))
            if out["output_type"] in ("execute_result", "display_data") and \
                    _SYMPY_TEXT.search(text) and "text/latex" not in data:
                plain_only.append((i, text[:60]))
    assert plain_only == [], f"{path.name}: SymPy shown as plain text in cells {plain_only}"


def test_formulas_keep_a_deterministic_plain_text():
    import sympy as sp

    from photolib import nb

    a = sp.Symbol("alpha")
    f = nb.formulas(sp.Matrix([[sp.cos(a), -sp.sin(a)]]), sp.Eq(sp.Symbol("r"), a))
    latex = f._repr_latex_()
    assert latex.startswith("$\\displaystyle ") and latex.endswith("$")
    assert "\\cos{\\left(\\alpha \\right)}" in latex and "r = \\alpha" in latex
    assert repr(f) == "(Matrix([[cos(alpha), -sin(alpha)]]), Eq(r, alpha))"
    assert repr(nb.formulas(a)) == "alpha"
