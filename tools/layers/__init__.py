# SPDX-License-Identifier: GPL-3.0-or-later
"""layers: the layer rule of src/ and include/stabdae (main.py; run by tools/layers/layers)."""
