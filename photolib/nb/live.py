"""Live figures for widgets: matplotlib rendered to PNG into an ``ipywidgets.Output``.

Why not ``with output: display(fig)``? Two reasons, both measured:

* Speed. A full matplotlib draw plus PNG encoding of a 3-D figure takes 100–200 ms on a
  course laptop; a slider then lags. :class:`LiveFigure` draws the static part (axes, ticks,
  object frame) once, keeps that background, and per update redraws only the artists that
  move ("blitting", as matplotlib's animation module does) and encodes the PNG with fast
  compression: about 10 ms.
* Reproducible notebooks. Output captured by ``with output:`` is routed by the *frontend*;
  ``jupyter nbconvert --execute`` stores it in the widget state, while nbval (which ignores
  widget messages) sees it as cell output, so the committed notebook and the test disagree.
  :class:`LiveFigure` sets the ``outputs`` of the Output widget directly, a widget-state
  update only: the cell's own output is just the widget, the same everywhere.

The figure is a plain :class:`matplotlib.figure.Figure` on the Agg canvas, not a pyplot
figure, so the inline backend never shows it a second time at the end of the cell.
"""

from __future__ import annotations

import base64
import io

import ipywidgets as widgets
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

__all__ = ["Explorer", "LiveFigure", "Panel", "finished", "slider"]


class LiveFigure:
    """A figure whose moving artists are redrawn on a cached background.

    Parameters
    ----------
    figsize : tuple of float
        Width and height in inches.
    dpi : float
        Resolution of the PNG.

    Add axes with ``live.figure.add_subplot`` and mark moving artists with :meth:`animate`.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
    output : ipywidgets.Output
        Shows the last rendered PNG.
    png : bytes
        The last rendered PNG.

    Examples
    --------
    >>> live = LiveFigure((3, 2))
    >>> ax = live.figure.add_subplot()
    >>> line = live.animate(ax.plot([0, 1], [0, 1])[0])
    >>> first = live.render()
    >>> line.set_ydata([1, 0])
    >>> live.render() != first
    True
    """

    def __init__(self, figsize, dpi: float = 80):
        self.figure = Figure(figsize=figsize, dpi=dpi)
        FigureCanvasAgg(self.figure)
        # never shrunk by a flex box: a narrow notebook column would crop the PNG's right edge
        self.output = widgets.Output(layout=widgets.Layout(flex="0 0 auto"))
        self.png = b""
        self._animated: list = []
        self._background = None

    def animate(self, artist):
        """Mark ``artist`` as moving: drawn on every :meth:`render`; returns it."""
        artist.set_animated(True)
        self._animated.append(artist)
        return artist

    def invalidate(self) -> None:
        """Forget the cached background (after changing a static artist or a limit)."""
        self._background = None

    def render(self) -> bytes:
        """Redraw the moving artists, encode a PNG and show it in :attr:`output`."""
        canvas = self.figure.canvas
        if self._background is None:
            canvas.draw()  # draws everything not animated
            self._background = canvas.copy_from_bbox(self.figure.bbox)
        else:
            canvas.restore_region(self._background)
        renderer = canvas.get_renderer()
        for artist in self._animated:
            if not artist.get_visible():
                continue
            if hasattr(artist, "do_3d_projection"):
                artist.do_3d_projection()
            artist.draw(renderer)
        buf = np.asarray(canvas.buffer_rgba())
        image = Image.fromarray(buf[..., :3].copy())
        stream = io.BytesIO()
        image.save(stream, format="png", compress_level=1)
        self.png = stream.getvalue()
        self.output.outputs = ({
            "output_type": "display_data",
            "data": {"image/png": base64.b64encode(self.png).decode("ascii"),
                     "text/plain": "<Figure>"},
            "metadata": {},
        },)
        return self.png


class Panel(widgets.VBox):
    """A ``VBox`` whose plain-text form is a short title, not the repr of every child.

    The text form is what a notebook stores beside the widget and what nbval compares;
    a child's repr would contain the rendered PNG.

    Examples
    --------
    >>> repr(Panel(title="demo"))
    '[widget: demo]'
    """

    def __init__(self, children=(), title: str = "", **kwargs):
        super().__init__(children=list(children), **kwargs)
        self._title = title
        self.add_class("photolib-explorer")  # found by tests/browser/test_lab.py

    def __repr__(self) -> str:
        return f"[widget: {self._title}]"


def finished(fig):
    """``fig``, complete, marked as not stale so that it is rendered once, not twice.

    In IPython, pyplot's post-execute hook redraws every *stale* figure on its Agg canvas
    (``draw_idle``) and then the inline backend draws the figure again to make the PNG;
    the first draw is thrown away (some 0.1 s per figure). Changing the figure afterwards
    marks it stale again, so a figure that is extended still gets redrawn.
    """
    fig.stale = False
    return fig


def slider(description: str, value: float, vmin: float, vmax: float, step: float,
           fmt: str = ".1f", width: str = "330px") -> widgets.FloatSlider:
    """A live-updating ``FloatSlider`` with the course's layout.

    ``continuous_update=True``: the callbacks are fast enough (``benchmarks/bench_widgets.py``).

    >>> s = slider("ω [°]", 10.0, -180.0, 180.0, 1.0)
    >>> s.value, s.continuous_update
    (10.0, True)
    """
    return widgets.FloatSlider(
        value=value, min=vmin, max=vmax, step=step, description=description,
        continuous_update=True, readout_format=fmt,
        style={"description_width": "110px"}, layout=widgets.Layout(width=width))


class Explorer:
    """Base of the course's widgets: sliders → :meth:`update` → figure and text.

    Subclasses set :attr:`title`, build ``self.controls`` (name → widget) and
    ``self.live`` (:class:`LiveFigure`) in ``__init__``, implement :meth:`draw`
    (values → HTML text, after moving the artists) and call :meth:`_finish`.

    Attributes
    ----------
    controls : dict of str to ipywidgets.ValueWidget
    html : ipywidgets.HTML
        The numbers that go with the picture.
    widget : Panel
        What the notebook displays.
    """

    title = "explorer"

    def _finish(self) -> None:
        self.html = widgets.HTML(layout=widgets.Layout(min_width="260px"))
        box = widgets.VBox(list(self.controls.values()))
        # the text wraps below the figure where the column is too narrow for both
        row = widgets.HBox([self.live.output, self.html],
                           layout=widgets.Layout(flex_flow="row wrap"))
        self.widget = Panel([box, row], title=self.title)
        for control in self.controls.values():
            control.observe(self._on_change, names="value")
        self.update()

    def values(self) -> dict:
        """The current control values, by name."""
        return {name: c.value for name, c in self.controls.items()}

    def _on_change(self, change) -> None:
        self.update()

    def set(self, **values) -> None:
        """Set controls without triggering one redraw per control, then redraw once."""
        handlers = [(c, self._on_change) for c in self.controls.values()]
        for c, h in handlers:
            c.unobserve(h, names="value")
        try:
            for name, value in values.items():
                self.controls[name].value = value
        finally:
            for c, h in handlers:
                c.observe(h, names="value")
        self.update()

    def update(self) -> str:
        """Redraw from the current control values; returns the HTML text shown."""
        text = self.draw(**self.values())
        self.html.value = text
        self.live.render()
        return text

    def draw(self, **values) -> str:  # pragma: no cover - abstract
        raise NotImplementedError

    def _ipython_display_(self):
        from IPython.display import display

        display(self.widget)
