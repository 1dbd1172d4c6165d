# Sphinx configuration of the stonedem documentation.
# Build: python3 -m pip install -e '.[docs]' && python3 -m sphinx -W -b html docs docs/_build/html
# Pages are MyST Markdown; the results pages read their tables from results/ at build time
# (docs/_ext/results_tables.py), the key tables from the input specs (docs/_ext/input_keys.py);
# the gallery runs every script of examples/ (sphinx-gallery).
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

from stonedem.version import __version__  # noqa: E402  (the package is installed: pip install -e .)

project = "stonedem"
author = "the stonedem authors"
copyright = "the stonedem authors"
release = __version__
version = __version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx_gallery.gen_gallery",
    "results_tables",
    "input_keys",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "_ext", "Thumbs.db", ".DS_Store"]

# MyST: $...$ and $$...$$ math, ::: fences, definition lists; anchors for ## and ### headings
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# API reference: the docstrings are written for the reader of the source (plain prose,
# numpy sections where a function has many parameters), not for numpydoc's validator
autodoc_member_order = "bysource"
autodoc_typehints = "none"
autosummary_generate = False
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks = set()
numpydoc_xref_param_type = False

# every example in examples/ is executed at build time; one that raises fails the build
sphinx_gallery_conf = {
    "examples_dirs": "../examples",
    "gallery_dirs": "gallery",
    "filename_pattern": r".*",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "show_memory": False,
    "remove_config_comments": True,
}

html_theme = "furo"
html_title = f"stonedem {release}"
html_static_path = []
