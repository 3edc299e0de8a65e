"""Build the course website: the executed chapter notebooks as a static HTML site.

``make site`` runs this with the site environment (Sphinx, myst-nb, sphinx-book-theme from
PyPI; MathJax from the npm registry, ``site/package.json``). Nothing is executed: the pages
show the committed outputs. Steps:

1. Stage ``notebooks/*.ipynb`` (in the course's chapter order) and the student copies
   ``exercises/*.ipynb`` into ``<out>/src``. Every widget output becomes its first state as
   static HTML: the figure as the PNG the notebook stored, the controls with their start values
   and the text beside the figure (the widgets' saved state, ``metadata.widgets``). The saved
   state itself is dropped, so the page loads no widget JavaScript from a CDN.
2. The glossary becomes a page of its own with one table per chapter, written from
   :mod:`photolib.glossary`, so that the site's search finds every term in every language.
3. Links to ``.ipynb`` files in raw HTML outputs point to the built ``.html`` pages.
4. ``sphinx-build`` writes ``<out>/html``; MathJax is copied to ``_static/mathjax``.

Usage: ``python site/build_site.py [--out build/site]``.
"""

from __future__ import annotations

import argparse
import html
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SITE = ROOT / "site"

#: the notebooks in the order of the table of contents
CHAPTERS = ["00-start", "01-introduction", "02-optics", "03-digital-images", "04-rotations",
            "05-interior-orientation", "06-collinearity", "07-plane-transformations",
            "08-resection-dlt", "09-stereo", "10-bundle-adjustment", "11-image-measurement",
            "12-products", "13-errata", "14-project"]

_WIDGET = "application/vnd.jupyter.widget-view+json"
_STATE = "application/vnd.jupyter.widget-state+json"
_CONTROLS = {"FloatSliderModel", "IntSliderModel", "FloatLogSliderModel", "DropdownModel",
             "ToggleButtonsModel", "CheckboxModel", "RadioButtonsModel", "SelectionSliderModel",
             "FloatRangeSliderModel", "IntRangeSliderModel", "ToggleButtonModel", "TextModel",
             "BoundedFloatTextModel", "BoundedIntTextModel", "FloatTextModel", "IntTextModel"}


class SiteError(RuntimeError):
    """The site cannot be built as asked (a missing notebook, a widget without saved state)."""


def _model_id(ref: str) -> str:
    return ref[len("IPY_MODEL_"):] if ref.startswith("IPY_MODEL_") else ref


def _control_value(state: dict) -> str:
    if "_options_labels" in state and state.get("index") is not None:
        index = state["index"]
        labels = state["_options_labels"]
        if isinstance(index, list):
            return ", ".join(labels[i] for i in index)
        return labels[index]
    value = state.get("value")
    fmt = state.get("readout_format")
    if isinstance(value, (int, float)) and not isinstance(value, bool) and fmt:
        try:
            return format(value, fmt)
        except ValueError:
            pass
    return str(value)


def _output_html(output: dict) -> str:
    data = output.get("data", {})
    if output.get("output_type") == "stream":
        return f"<pre>{html.escape(''.join(output.get('text', '')))}</pre>"
    if "image/png" in data:
        png = data["image/png"]
        png = "".join(png) if isinstance(png, list) else png
        size = output.get("metadata", {}).get("image/png", {})
        width = f' width="{int(size["width"])}"' if "width" in size else ""
        return f'<img src="data:image/png;base64,{png}"{width} alt="widget figure">'
    if "text/html" in data:
        return "".join(data["text/html"])
    if "text/plain" in data:
        return f"<pre>{html.escape(''.join(data['text/plain']))}</pre>"
    return ""


def widget_html(model_id: str, state: dict, title: str = "") -> str:
    """The first state of a widget as static HTML (figure, controls, text).

    ``state`` is the notebook's saved widget state (model id → ``{"model_name", "state"}``).
    Raises :class:`SiteError` when the model is not in it.
    """
    if model_id not in state:
        raise SiteError(f"widget model {model_id} is not in the notebook's saved widget state")
    controls: list[tuple[str, str]] = []

    def walk(mid: str) -> str:
        entry = state.get(mid)
        if entry is None:
            return ""
        name, s = entry["model_name"], entry["state"]
        if name in ("VBoxModel", "HBoxModel", "BoxModel", "GridBoxModel"):
            parts = [walk(_model_id(c)) for c in s.get("children", [])]
            parts = [p for p in parts if p]
            cls = "figure-row" if name == "HBoxModel" else "column"
            return f'<div class="{cls}">' + "".join(parts) + "</div>" if parts else ""
        if name == "OutputModel":
            return "".join(_output_html(o) for o in s.get("outputs", []))
        if name in ("HTMLModel", "HTMLMathModel"):
            return f'<div class="text">{s.get("value", "")}</div>'
        if name == "LabelModel":
            return f"<div>{html.escape(str(s.get('value', '')))}</div>"
        if name in _CONTROLS:
            controls.append((s.get("description", ""), _control_value(s)))
            return ""
        return ""

    body = walk(model_id)
    rows = "".join(f"<tr><td>{html.escape(d)}</td><td>{html.escape(v)}</td></tr>"
                   for d, v in controls)
    head = f'<div class="title">{html.escape(title)}</div>' if title else ""
    note = ('<div class="note">Interactive in JupyterLab (<code>make lab</code>); '
            "here the widget's first state.</div>")
    table = f'<table class="controls">{rows}</table>' if rows else ""
    return f'<div class="photolib-static-widget">{head}{note}{table}{body}</div>'


def _ipynb_links(text: str) -> str:
    """``href="x.ipynb"`` (and ``#anchors``) in raw HTML → the built page ``x.html``."""
    return re.sub(r'href="([^":#]+)\.ipynb(#[^"]*)?"', lambda m: f'href="{m.group(1)}.html'
                  f'{m.group(2) or ""}"', text)


def static_notebook(nb: dict) -> dict:
    """The notebook with every widget output replaced by its static first state."""
    state = nb.get("metadata", {}).get("widgets", {}).get(_STATE, {}).get("state", {})
    for cell in nb["cells"]:
        if cell["cell_type"] == "markdown":
            source = "".join(cell["source"])
            # the glossary notebook is the site's glossary page, one folder up
            cell["source"] = re.sub(r"\(glossary\.ipynb", "(../glossary.md", source)
            continue
        if cell["cell_type"] != "code":
            continue
        outputs = []
        for out in cell.get("outputs", []):
            data = out.get("data", {})
            if _WIDGET in data:
                title = "".join(data.get("text/plain", ""))
                title = re.sub(r"^\[widget: (.*)\]$", r"\1", title.strip())
                outputs.append({"output_type": "display_data", "metadata": {},
                                "data": {"text/html": widget_html(data[_WIDGET]["model_id"],
                                                                  state, title)}})
                continue
            if "text/html" in data:
                data["text/html"] = _ipynb_links("".join(data["text/html"]))
            outputs.append(out)
        cell["outputs"] = outputs
    nb.get("metadata", {}).pop("widgets", None)
    return nb


def glossary_markdown() -> str:
    """The glossary page: one table per chapter, every term in its four languages."""
    from photolib import glossary as g

    lines = ["# Glossary / Glossar / Słownik / Szójegyzék", "",
             "The terms of the course's four sources in English, German, Polish and Hungarian, "
             "each linked to the chapter that teaches it (the site's search finds a term in any "
             "of the four languages). In JupyterLab the glossary notebook filters them as you "
             "type.", ""]
    terms = g.load_glossary()
    for chapter in dict.fromkeys(t.chapter for t in terms):
        lines += [f"## [{chapter}](notebooks/{chapter}.ipynb)", "",
                  "| English | Deutsch | Polski | Magyar | sources |",
                  "|---|---|---|---|---|"]
        for t in (t for t in terms if t.chapter == chapter):
            cells = [t.en, t.de, t.pl, t.hu, ", ".join(t.sources)]
            lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
        lines.append("")
    return "\n".join(lines)


def index_markdown(titles: dict) -> str:
    chapters = "\n".join(f"notebooks/{c}" for c in CHAPTERS)
    exercises = "\n".join(f"exercises/{c}" for c in CHAPTERS if c in titles["exercises"])
    return f"""# photolib: a photogrammetry course that checks its own mathematics

A photogrammetry course in fifteen chapters: every formula derived in SymPy and checked,
every method built in readable code before the library call, real photographs measured,
calibrated, oriented and mapped. This site shows the chapters as they were executed; run them
and their widgets in JupyterLab with `make lab`, and solve the graded exercises there.

```{{toctree}}
:caption: Chapters
:maxdepth: 1

{chapters}
glossary
```

```{{toctree}}
:caption: Exercises (student copies)
:maxdepth: 1

{exercises}
```
"""


def stage(out: Path) -> Path:
    src = out / "src"
    if src.exists():
        shutil.rmtree(src)
    (src / "notebooks").mkdir(parents=True)
    (src / "exercises").mkdir(parents=True)
    titles = {"exercises": set()}
    for chapter in CHAPTERS:
        path = ROOT / "notebooks" / f"{chapter}.ipynb"
        if not path.exists():
            raise SiteError(f"chapter notebook {path} is missing")
        nb = static_notebook(json.loads(path.read_text(encoding="utf-8")))
        (src / "notebooks" / path.name).write_text(json.dumps(nb), encoding="utf-8")
        copy = ROOT / "exercises" / f"{chapter}.ipynb"
        if copy.exists():
            nb = static_notebook(json.loads(copy.read_text(encoding="utf-8")))
            (src / "exercises" / copy.name).write_text(json.dumps(nb), encoding="utf-8")
            titles["exercises"].add(chapter)
    (src / "glossary.md").write_text(glossary_markdown(), encoding="utf-8")
    (src / "index.md").write_text(index_markdown(titles), encoding="utf-8")
    shutil.copy(SITE / "conf.py", src / "conf.py")
    shutil.copytree(SITE / "_static", src / "_static")
    mathjax = SITE / "node_modules" / "mathjax" / "es5"
    if not (mathjax / "tex-mml-chtml.js").exists():
        raise SiteError(f"MathJax is not installed in {mathjax}: run 'npm ci' in site/ "
                        "(make site does)")
    target = src / "_static" / "mathjax"
    target.mkdir()
    shutil.copy(mathjax / "tex-mml-chtml.js", target / "tex-mml-chtml.js")
    shutil.copytree(mathjax / "output" / "chtml" / "fonts", target / "output" / "chtml" / "fonts")
    return src


def build(out: Path) -> Path:
    src = stage(out)
    html_dir = out / "html"
    if html_dir.exists():
        shutil.rmtree(html_dir)
    cmd = [sys.executable, "-m", "sphinx", "-b", "html", "-q", "-j", "2",
           "-d", str(out / "doctrees"), str(src), str(html_dir)]
    subprocess.run(cmd, check=True)
    return html_dir


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "build" / "site")
    args = parser.parse_args(argv)
    html_dir = build(args.out.resolve())
    print(f"site written to {html_dir / 'index.html'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
