# SPDX-License-Identifier: GPL-3.0-or-later
"""figures: the demo's plots, each a module run as python -m figures.NAME with tools/ on
PYTHONPATH (tools/demo runs both)."""
