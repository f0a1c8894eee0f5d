"""Sphinx configuration: MyST Markdown pages, the reference generated from the code."""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE / '_ext'), str(HERE.parent / 'src')]

project = 'turtle_traj'
author = 'the turtle_traj developers'
extensions = [
    'myst_parser',  # Markdown pages, as ROS 2's documentation and rosdoc2 use
    'sphinx.ext.autodoc',  # the Python API from docstrings
    'sphinxarg.ext',  # the command line from argparse
    'turtle_traj_reference',  # parameters and interfaces from the parameter table and registry
]
source_suffix = {'.md': 'markdown'}
myst_enable_extensions = ['colon_fence', 'deflist']
myst_heading_anchors = 3
html_theme = 'furo'
html_title = 'turtle_traj'
exclude_patterns = ['_build']
autodoc_member_order = 'bysource'
autodoc_typehints = 'description'
nitpicky = False
suppress_warnings = ['myst.xref_missing']  # links to files of the repository, not pages
