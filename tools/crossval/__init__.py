# SPDX-License-Identifier: GPL-3.0-or-later
"""crossval: the cross-validation harness of stabdae (run by tools/crossval/crossval).

It runs the C example programs (build/examples/*), the Python reference (tools/stabdae_ref,
float64 and mpmath) and the SUNDIALS IDA reference (build/tools/ida_reference), checks

  a  same discrete scheme: C against the mpmath reference           (check_scheme)
  b  observed orders on the manifold against exact / high-precision   (check_order)
     references, and IDA against the exact solutions
  c  decay of xi off the manifold (scheme 15) and scheme 11's          (check_offmanifold)
     step bound on a constant gain
  d  conservation of W by dgrad over 1e6 steps, IDA's energy drift       (check_energy)
  e  constraint drift: index reduction, Baumgarte, the paper          (check_drift)
  f  the mechanical front-end's examples (pendulum_mbs,               (check_mbs)
     double_pendulum): orders against the exact pendulum and the
     double pendulum in angles, energy by dgrad, constraint drift

and writes a Markdown report with PNG plots (report). Modules: runs (running the three
implementations), profiles (the fast and full settings), plots, report, main.
"""
