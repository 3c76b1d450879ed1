# SPDX-License-Identifier: GPL-3.0-or-later
"""One step of scheme 11 or 15 and the fixed-step run.

From the current (xi, mu), Q = Q(xi, mu) is evaluated once, and
  gains     k_i = -(delta^2/2) ||q_i||^2 - eps                              (eq. 6)
  scheme 11 xi_i+ = (1 + T k_i) xi_i                                        (eq. 11)
  scheme 15 xi_i+ = xi_i / (1 - T k_i)                                      (eq. 15)
  mu+       mu+ = mu + T (phi_T(mu, mu+) + Q xi)                            (eq. 11, 15)
solved by Newton for an implicit map from mu + T (phi_T(mu, mu) + Q xi).

Baselines (stabilizer 'none' and 'baumgarte') replace the xi update by the chain of each
constraint, xi_j' = xi_{j+1} with the last derivative 0 ('none', index reduction, which drifts:
xi_1(t) = xi_1(0) + t xi_2(0)) or -sum_j alpha_j xi_j ('baumgarte'): xi' = A xi, discretized as
xi+ = xi + T A xi (scheme 11) or (I - T A) xi+ = xi (scheme 15). The mu update is the same.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING

from . import maps, vec
from .arith import Matrix, Num, Vector
from .models import Model

if TYPE_CHECKING:
    from .api import Result

SCHEMES = (11, 15)
STABILIZERS = ("paper", "none", "baumgarte")


class StepFailure(Exception):
    """A step could not be taken; `step` is the number of the step that failed."""

    result: Result  # the rows computed before, set by api.simulate

    def __init__(self, step: int, t: Num, reason: str) -> None:
        super().__init__("step %d from t = %s failed: %s" % (step, t, reason))
        self.step, self.t, self.reason = step, t, reason


class Stepper:
    """The step of one model with one scheme, map and stabilizer (see the module docstring)."""

    def __init__(
        self,
        model: Model,
        scheme: int = 15,
        map: str = "dgrad",
        stabilizer: str = "paper",
        delta: float = 2.0,
        eps: float = 1.0,
        alpha: Sequence[float] = (1.0, 2.0),
    ) -> None:
        a = model.a
        if scheme not in SCHEMES:
            raise ValueError("scheme must be 11 or 15, got %r" % (scheme,))
        if stabilizer not in STABILIZERS:
            raise ValueError("stabilizer must be paper, none or baumgarte, got %r" % (stabilizer,))
        if not all(math.isfinite(float(v)) and float(v) > 0 for v in (delta, eps)):
            raise ValueError("delta and eps must be finite and > 0, got %r, %r" % (delta, eps))
        if not all(math.isfinite(float(v)) for v in alpha):
            raise ValueError("alpha must be finite, got %r" % (alpha,))
        self.model, self.a, self.scheme, self.stabilizer = model, a, scheme, stabilizer
        self.delta, self.eps = a.num(float(delta)), a.num(float(eps))
        self.alpha = [a.num(float(v)) for v in alpha]
        if stabilizer == "baumgarte" and any(r != len(self.alpha) for r in model.rel_degree):
            raise ValueError("baumgarte needs one alpha per derivative (%d)" % model.rel_degree[0])
        self.map = maps.make(map, model)

    def gains(self, Qm: Matrix) -> Vector:
        """eq. 6 from the columns of Q."""
        half_d2 = self.delta * self.delta / 2
        return [
            -half_d2 * sum(row[i] * row[i] for row in Qm) - self.eps for i in range(self.model.n_xi)
        ]

    def xi_paper(self, xi: Vector, Qm: Matrix, T: Num) -> Vector:
        k = self.gains(Qm)
        if self.scheme == 11:
            return [(1 + T * ki) * x for ki, x in zip(k, xi)]  # eq. 11
        return [x / (1 - T * ki) for ki, x in zip(k, xi)]  # eq. 15

    def chain_matrix(self, r: int) -> Matrix:
        """A of one constraint's chain xi_j' = xi_{j+1}, last row 0 or -alpha."""
        A: Matrix = [[1 if j == i + 1 else 0 for j in range(r)] for i in range(r)]
        if self.stabilizer == "baumgarte":
            A[r - 1] = [-al for al in self.alpha]
        return A

    def xi_baseline(self, xi: Vector, T: Num) -> Vector:
        out, start = [], 0
        for r in self.model.rel_degree:
            block, A = xi[start : start + r], self.chain_matrix(r)
            if self.scheme == 11:
                out += vec.add(block, vec.scale(T, vec.matvec(A, block)))
            else:
                M = [[(1 if i == j else 0) - T * A[i][j] for j in range(r)] for i in range(r)]
                out += self.a.solve(M, block)
            start += r
        return out

    def mu_next(self, mu: Vector, Qxi: Vector, T: Num) -> tuple[Vector, int]:
        """(mu+, Newton iterations) of mu+ = mu + T (phi_T(mu, mu+) + Q xi)."""
        a = self.a
        guess = vec.add(mu, vec.scale(T, vec.add(self.map.phi_T(mu, mu, T), Qxi)))
        if self.map.explicit:
            return guess, 0
        y, n = guess, len(mu)
        for it in range(1, a.newton_max_iter + 1):
            phi_y, dphi = self.map.phi_jac(mu, y)
            R = vec.sub(vec.sub(y, mu), vec.scale(T, vec.add(phi_y, Qxi)))
            if a.residual_small(R):
                return y, it - 1
            J = [[(1 if i == j else 0) - T * dphi[i][j] for j in range(n)] for i in range(n)]
            dy = a.solve(J, [-r for r in R])
            y = vec.add(y, dy)
            if a.update_small(dy, y):
                return y, it
        raise ArithmeticError("Newton did not converge in %d iterations" % a.newton_max_iter)

    def step(self, xi: Vector, mu: Vector, T: Num) -> tuple[Vector, Vector, int]:
        """(xi+, mu+, Newton iterations); raises ArithmeticError or ValueError on failure."""
        Qm = self.model.Q(xi, mu)
        Qxi = vec.matvec(Qm, xi)
        if self.stabilizer == "paper":
            xi_new = self.xi_paper(xi, Qm, T)
        else:
            xi_new = self.xi_baseline(xi, T)
        mu_new, iters = self.mu_next(mu, Qxi, T)
        if not all(self.a.isfinite(v) for v in xi_new + mu_new):
            raise ArithmeticError("the new state is not finite")
        self.model.admissible(xi_new, mu_new)
        return xi_new, mu_new, iters


def run(
    stepper: Stepper, xi: Vector, mu: Vector, T: Num, nsteps: int, every: int = 1
) -> Iterator[tuple[int, Num, Vector, Vector, int]]:
    """Yields (step, t, xi, mu, newton_iters) for step 0, every `every`-th step and the last;
    t = step T. Raises StepFailure (after yielding what was computed) when a step fails."""
    if every < 1 or int(every) != every:
        raise ValueError("every must be a positive integer, got %r" % (every,))
    yield 0, 0 * T, xi, mu, 0
    for n in range(1, nsteps + 1):
        try:
            xi, mu, iters = stepper.step(xi, mu, T)
        except (ArithmeticError, ValueError) as exc:
            raise StepFailure(n, (n - 1) * T, str(exc)) from exc
        if n % every == 0 or n == nsteps:
            yield n, n * T, xi, mu, iters
