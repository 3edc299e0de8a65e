"""What every explorer test asks of a widget, written once for the ``tests/test_nb*.py`` files.

Import relatively (``from .explorer_checks import moves``): under ``--import-mode=importlib``
the test modules are ``tests.test_nb_*`` and this module is ``tests.explorer_checks``. The
figures are closed after each test by the ``close_figures`` fixture of ``tests/conftest.py``.
"""

from __future__ import annotations


def moves(explorer, name, value):
    """Set slider ``name`` to ``value``: (did the PNG change, did the text change)."""
    before_png, before_html = explorer.live.png, explorer.html.value
    explorer.controls[name].value = value
    return explorer.live.png != before_png, explorer.html.value != before_html


def assert_every_value_redraws(cls, name, values):
    """A fresh ``cls()`` redraws (figure or text) each time slider ``name`` moves to the next of
    ``values``. How fast it redraws is measured in ``benchmarks/bench_widgets.py`` (target
    50 ms), not here: a timed test would only measure how busy the test machine is."""
    explorer = cls()
    for value in values:
        if explorer.controls[name].value == value:
            continue
        assert any(moves(explorer, name, value)), f"{cls.__name__}: {name} = {value!r} redrew nothing"


def assert_explorer_widget(explorer, title):
    """The widget shows as ``[widget: title]`` and carries the ``photolib-explorer`` class."""
    assert repr(explorer.widget) == f"[widget: {title}]"
    assert "photolib-explorer" in explorer.widget._dom_classes


# -- what a student sees: the figure's layout, measured with matplotlib's renderer -------------

def all_explorers():
    """Every explorer class of ``photolib.nb`` (subclasses of :class:`photolib.nb.live.Explorer`)."""
    import importlib
    import inspect
    import pkgutil

    import photolib.nb as nbpkg
    from photolib.nb.live import Explorer

    found = []
    for info in pkgutil.iter_modules(nbpkg.__path__):
        module = importlib.import_module(f"photolib.nb.{info.name}")
        for obj in vars(module).values():
            if (inspect.isclass(obj) and issubclass(obj, Explorer) and obj is not Explorer
                    and obj.__module__ == module.__name__):
                found.append(obj)
    return sorted(found, key=lambda c: (c.__module__, c.__name__))


def drawn(fig):
    """Draw ``fig`` completely (animated artists too) and return its renderer."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    return renderer


def outside_figure(fig):
    """Texts of the axes (labels, titles, tick labels) that reach beyond the figure's edge,
    as ``(axes title, bbox extents)``: what a student sees cut off."""
    renderer = drawn(fig)
    box = fig.bbox
    cut = []
    for ax in fig.axes:
        tight = ax.get_tightbbox(renderer)
        if tight is None:
            continue
        if (tight.x0 < box.x0 - 0.5 or tight.y0 < box.y0 - 0.5 or tight.x1 > box.x1 + 0.5
                or tight.y1 > box.y1 + 0.5):
            cut.append((ax.get_title(), tuple(round(float(v)) for v in tight.extents)))
    return cut


def tick_label_boxes_3d(ax, renderer):
    """``(axis name + label text, bbox)`` of every tick label a 3-D axes draws.

    A 3-D axis places its tick labels while it draws (``Axis3D._update_all_positions``
    yields them placed, as ``draw`` and ``get_tightbbox`` use it); the boxes are read there.
    """
    boxes = []
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        for updated in axis._update_all_positions():
            for tick in updated.ticks or ():
                label = tick.label1
                if label.get_visible() and label.get_text():
                    boxes.append((axis.axis_name + label.get_text(), label.get_window_extent(renderer)))
    return boxes


def overlapping_ticks_3d(fig):
    """Pairs of tick labels of the 3-D axes of ``fig`` whose boxes overlap."""
    renderer = drawn(fig)
    pairs = []
    for ax in fig.axes:
        if not hasattr(ax, "zaxis"):
            continue
        boxes = tick_label_boxes_3d(ax, renderer)
        pairs += [(a, b) for i, (a, ba) in enumerate(boxes) for b, bb in boxes[i + 1:]
                  if ba.overlaps(bb)]
    return pairs


def legend_covers(fig):
    """Data points (line vertices, scatter offsets) under a legend: ``(axes title, count)``."""
    import numpy as np
    from matplotlib.lines import Line2D

    renderer = drawn(fig)
    covered = []
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is None:
            continue
        box = legend.get_window_extent(renderer)
        count = 0
        for artist in ax.lines + ax.collections:
            if not artist.get_visible():
                continue
            if isinstance(artist, Line2D):
                xy = np.asarray(artist.get_xydata(), dtype=float)
                points = artist.get_transform().transform(xy) if len(xy) else xy
            else:
                offsets = np.asarray(artist.get_offsets(), dtype=float)
                points = artist.get_offset_transform().transform(offsets) if len(offsets) else offsets
            if not len(points):
                continue
            points = points[np.isfinite(points).all(axis=1)]
            if artist.get_clip_on():      # clipped vertices outside the axes are not drawn
                frame = ax.get_window_extent(renderer)
                points = points[(points[:, 0] >= frame.x0) & (points[:, 0] <= frame.x1)
                                & (points[:, 1] >= frame.y0) & (points[:, 1] <= frame.y1)]
            count += int(np.sum((points[:, 0] > box.x0) & (points[:, 0] < box.x1)
                                & (points[:, 1] > box.y0) & (points[:, 1] < box.y1)))
        if count:
            covered.append((ax.get_title(), count))
    return covered


def slider_values(control, n=5):
    """``n`` values from the minimum to the maximum of a slider, on its steps."""
    import numpy as np

    steps = np.round(np.linspace(0.0, 1.0, n) * (control.max - control.min) / control.step)
    return [float(control.min + k * control.step) for k in steps]
