# SPDX-License-Identifier: GPL-3.0-or-later
"""stabdae_gen: a mechanism described in sympy, written as C for <stabdae/mbs.h>.

    from stabdae_gen import Mechanism
    def mechanism():
        return Mechanism("pendulum", t, [x, y], [vx, vy], kinetic=..., potential=...,
                         constraints=[...], params={...}, q0=[...], v0=[...])

`tools/mbsgen MODEL.py --out DIR` (or `python -m stabdae_gen`) writes DIR/name.h and
DIR/name.c; docs/generator.md is the tutorial and the reference.
"""

from .errors import ModelError
from .mechanics import from_lagranges_method, from_system
from .mechanism import Mechanism

__version__ = "0.1.0"  # the project's version (CMakeLists.txt), checked by the tests
__all__ = ["Mechanism", "ModelError", "from_lagranges_method", "from_system", "__version__"]
