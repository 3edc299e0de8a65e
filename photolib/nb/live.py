"""Live figures for widgets: matplotlib rendered to PNG into an ``ipywidgets.Output``.

Why not ``with output: display(fig)``? Two reasons, both measured:

* Speed. A full matplotlib draw plus PNG encoding of a 3-D figure takes 100–200 ms on a
  course laptop; a slider then lags. :class:`LiveFigure` draws the static part (axes, ticks,
  object frame) once, keeps that background, and per update redraws only the artists that
  move ("blitting", as matplotlib's animation module does) and encodes the PNG with fast
  compression (:func:`png_rgb`): about 10–20 ms at twice the CSS resolution.
* Reproducible notebooks. Output captured by ``with output:`` is routed by the *frontend*;
  ``jupyter nbconvert --execute`` stores it in the widget state, while nbval (which ignores
  widget messages) sees it as cell output, so the committed notebook and the test disagree.
  :class:`LiveFigure` sets the ``outputs`` of the Output widget directly, a widget-state
  update only: the cell's own output is just the widget, the same everywhere.

The figure is a plain :class:`matplotlib.figure.Figure` on the Agg canvas, not a pyplot
figure, so the inline backend never shows it a second time at the end of the cell.

Sharp on HiDPI screens: the PNG has :data:`PIXEL_RATIO` (2) device pixels per CSS pixel, and
its metadata gives the browser the CSS size (``figsize`` × 80 dpi), so a laptop with a device
pixel ratio of 2 shows every pixel of it and any other screen shows the same layout.

Sliders reach every value with the mouse: :func:`slider` makes the track at least one CSS
pixel per step wide, and the label column wide enough for the description
(:func:`label_width`); :meth:`Explorer._finish` gives all sliders of a widget the widest of
those, so their tracks line up.
"""

from __future__ import annotations

import base64
import functools
import math
import struct
import zlib

import ipywidgets as widgets
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from photolib.nb._table import _Controls

__all__ = ["CSS_DPI", "PIXEL_RATIO", "Explorer", "LiveFigure", "Panel", "align_sliders", "finished",
           "label_width", "png_rgb", "px", "slider", "slider_track_px"]

#: CSS pixels per inch of the widgets' figures (their layout size: ``figsize`` × 80)
CSS_DPI = 80
#: device pixels per CSS pixel of the widgets' PNGs: 2, the ratio of most HiDPI laptops
PIXEL_RATIO = 2


class LiveFigure:
    """A figure whose moving artists are redrawn on a cached background.

    Parameters
    ----------
    figsize : tuple of float
        Width and height in inches.
    dpi : float
        CSS pixels per inch: the size of the figure on the page is ``figsize`` × ``dpi``.
    pixel_ratio : float
        Device pixels per CSS pixel: the PNG is ``pixel_ratio`` times as wide and high as
        its size on the page (matplotlib draws it at ``dpi`` × ``pixel_ratio``, so fonts and
        lines keep their size on the page and get sharper).

    Add axes with ``live.figure.add_subplot`` and mark moving artists with :meth:`animate`.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
    output : ipywidgets.Output
        Shows the last rendered PNG.
    png : bytes
        The last rendered PNG.
    css_size : tuple of int
        (width, height) of the figure on the page, CSS pixels: the PNG's display metadata.

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

    def __init__(self, figsize, dpi: float = CSS_DPI, pixel_ratio: float = PIXEL_RATIO):
        self.figure = Figure(figsize=figsize, dpi=dpi * pixel_ratio)
        self.css_size = (round(figsize[0] * dpi), round(figsize[1] * dpi))
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
        self.png = png_rgb(np.asarray(canvas.buffer_rgba())[..., :3])
        self.output.outputs = ({
            "output_type": "display_data",
            "data": {"image/png": base64.b64encode(self.png).decode("ascii"),
                     "text/plain": "<Figure>"},
            # the browser lays the PNG out at its CSS size and shows all its pixels on HiDPI
            "metadata": {"image/png": {"width": self.css_size[0], "height": self.css_size[1]}},
        },)
        return self.png


def _png_chunk(tag: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))


def png_rgb(rgb) -> bytes:
    """A PNG of an (H, W, 3) ``uint8`` image: no row filter, zlib at its fastest level.

    Twice as fast as Pillow's encoder (which tries a filter per row) for the same size on
    the flat colours of a plot; a 2× widget figure (1.2 megapixels) takes some 10 ms.

    >>> from PIL import Image; import io
    >>> rgb = np.arange(24, dtype=np.uint8).reshape(2, 4, 3)
    >>> np.array_equal(np.asarray(Image.open(io.BytesIO(png_rgb(rgb)))), rgb)
    True
    """
    rgb = np.asarray(rgb, dtype=np.uint8)
    h, w, _ = rgb.shape
    raw = np.empty((h, 3 * w + 1), dtype=np.uint8)
    raw[:, 0] = 0                                  # filter type of each row: none
    raw[:, 1:] = rgb.reshape(h, 3 * w)
    header = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)  # 8 bit, truecolour
    return (b"\x89PNG\r\n\x1a\n" + _png_chunk(b"IHDR", header)
            + _png_chunk(b"IDAT", zlib.compress(raw.tobytes(), 1)) + _png_chunk(b"IEND", b""))


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


#: the CSS font of a widget label in JupyterLab (``--jp-widgets-font-size``), pixels
LABEL_FONT_PX = 13
#: CSS pixels of a slider besides its label and its track: the readout (72 px at least), the
#: track's and the label's margins, with some room
SLIDER_EXTRA_PX = 110
#: the shortest slider track, CSS pixels
MIN_TRACK_PX = 200


def px(length: str) -> float:
    """A CSS length in pixels (``"110px"`` → 110.0).

    >>> px("110px")
    110.0
    """
    if not length.endswith("px"):
        raise ValueError(f"not a length in px: {length!r}")
    return float(length[:-2])


@functools.lru_cache(maxsize=None)
def _text_width_px(text: str, size_px: float) -> float:
    from matplotlib import font_manager
    from matplotlib.ft2font import FT2Font

    font = FT2Font(font_manager.findfont(font_manager.FontProperties(family="DejaVu Sans")))
    font.set_size(size_px, 72)  # 72 dpi: points are pixels
    font.set_text(text, 0.0)
    return font.get_width_height()[0] / 64.0


def label_width(text: str, minimum: int = 110) -> int:
    """CSS pixels of a label column that shows ``text`` untruncated, a multiple of 10.

    Measured in DejaVu Sans (wider than the sans-serif fonts browsers usually pick) at the
    widgets' 13 px, with 15 % and 8 px to spare.

    >>> label_width("ω [°]"), label_width("target radius [px]")
    (110, 140)
    """
    need = 1.15 * _text_width_px(text, LABEL_FONT_PX) + 8.0
    return max(int(minimum), 10 * math.ceil(need / 10.0))


def slider_track_px(vmin: float, vmax: float, step: float) -> int:
    """CSS pixels of a track on which every step is at least one pixel wide.

    >>> slider_track_px(-180, 180, 1), slider_track_px(0, 10, 1)
    (360, 200)
    """
    return max(MIN_TRACK_PX, math.ceil(round((vmax - vmin) / step, 6)))


def slider(description: str, value: float, vmin: float, vmax: float, step: float,
           fmt: str = ".1f", width: str | None = None) -> widgets.FloatSlider:
    """A live-updating ``FloatSlider`` with the course's layout.

    ``continuous_update=True``: the callbacks are fast enough (``benchmarks/bench_widgets.py``).
    The label column fits the description (:func:`label_width`) and the track gives every
    step at least one CSS pixel (:func:`slider_track_px`), unless ``width`` says otherwise.

    >>> s = slider("ω [°]", 10.0, -180.0, 180.0, 1.0)
    >>> s.value, s.continuous_update, s.layout.width
    (10.0, True, '580px')
    """
    label = label_width(description)
    if width is None:
        width = f"{label + slider_track_px(vmin, vmax, step) + SLIDER_EXTRA_PX}px"
    return widgets.FloatSlider(
        value=value, min=vmin, max=vmax, step=step, description=description,
        continuous_update=True, readout_format=fmt,
        style={"description_width": f"{label}px"}, layout=widgets.Layout(width=width))


def align_sliders(controls) -> None:
    """Give every slider of ``controls`` the widest label column and the widest layout.

    The tracks then start and end at the same place, and none gets narrower.
    """
    sliders = [c for c in controls if isinstance(c, widgets.FloatSlider)
               and str(c.layout.width or "").endswith("px")
               and str(c.style.description_width or "").endswith("px")]
    if not sliders:
        return
    label = max(px(c.style.description_width) for c in sliders)
    track = max(px(c.layout.width) - px(c.style.description_width) for c in sliders)
    for c in sliders:
        c.style.description_width = f"{label:g}px"
        c.layout.width = f"{label + track:g}px"


class Explorer(_Controls):
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
        align_sliders(self.controls.values())
        box = widgets.VBox(list(self.controls.values()))
        # the text wraps below the figure where the column is too narrow for both
        row = widgets.HBox([self.live.output, self.html],
                           layout=widgets.Layout(flex_flow="row wrap"))
        self.widget = Panel([box, row], title=self.title)
        self._connect()

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
