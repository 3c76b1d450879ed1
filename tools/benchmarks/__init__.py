# SPDX-License-Identifier: GPL-3.0-or-later
"""benchmarks: the timing reports of stabdae, each a module run as python -m benchmarks.NAME
with tools/ on PYTHONPATH (tools/README.md); the C programs they run are built beside them."""
