"""Sphinx configuration of the course website (``make site``; see ``site/build_site.py``).

The chapter notebooks are shown as committed (executed, never re-run here: myst-nb with
execution off), MathJax is served from the site itself (``_static/mathjax``, from the npm
registry through ``site/package.json``), and the theme is sphinx-book-theme from PyPI: the
build and the built site need no network.
"""

project = "photolib: a photogrammetry course that checks its own mathematics"
author = "the photolib course authors"
language = "en"

extensions = ["myst_nb"]
nb_execution_mode = "off"            # the committed outputs are the course's outputs
nb_merge_streams = True
myst_enable_extensions = ["dollarmath", "amsmath", "html_image", "colon_fence"]
suppress_warnings = ["mystnb.unknown_mime_type", "myst.header", "misc.highlighting_failure"]

html_theme = "sphinx_book_theme"
html_title = "photolib course"
html_static_path = ["_static"]
html_css_files = ["course.css"]
html_theme_options = {
    "show_toc_level": 2,
    "use_download_button": False,
    "use_fullscreen_button": False,
    "use_repository_button": False,
    "navigation_with_keys": False,
}
html_copy_source = False
html_show_sourcelink = False
# MathJax 3 from the site itself; the configuration Sphinx writes keeps $…$ inline maths
mathjax_path = "mathjax/tex-mml-chtml.js"
mathjax3_config = {"tex": {"inlineMath": [["$", "$"], ["\\(", "\\)"]],
                           "processEscapes": True}}
exclude_patterns = ["_build", "node_modules", "**.ipynb_checkpoints"]
