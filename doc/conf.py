# Sphinx configuration for the PERI-NOSPD documentation.
# Build:  python3 -m sphinx -W -b html doc <output folder>
# Needs nothing beyond Sphinx itself (Debian: python3-sphinx); formulas are
# rendered by MathJax in the browser.

project = "PERI-NOSPD"
author = "PERI-NOSPD developers"
copyright = "2026, PERI-NOSPD developers"
release = "0.1"
version = release

extensions = []

root_doc = "index"
source_suffix = ".rst"
exclude_patterns = ["_build"]
language = "en"

# Input-script snippets are shown without highlighting (Pygments has no
# LAMMPS lexer).
highlight_language = "none"

html_theme = "alabaster"
html_title = "PERI-NOSPD"
html_show_sourcelink = False
