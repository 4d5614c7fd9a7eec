"""Newton's method on one step of the generalised-alpha scheme, for any model that
implements the protocol below: the solver knows the scheme's iteration, the model its
equations (as py-pde's solvers receive a PDE's right-hand side).

A step of the scheme (:mod:`.alpha_scheme`) leaves as unknowns the accelerations
``a_{n+1}`` of the free coordinates of ``R(q, v, a, t) = M(q) a + F(q, v, t) = 0``: the
auxiliary acceleration, the velocities and the coordinates follow them linearly (a
correction ``d`` of ``a`` moves ``abar`` by ``(1 - af)/(1 - am) d``, ``v`` by
``gamma' d`` and ``q`` by ``beta' d``). Newton iterates on ``a_{n+1}`` with the
iteration matrix ``M + gamma' C + beta' K``.

**Protocol.** A formulation registers a ``numba.extending.overload`` of each function
below for its own type of ``model`` (the first argument; :func:`overload_for`); ``step``
is whatever else the formulation needs (its state, workspace, time and scheme factors,
in a tuple of its own type). numerics never imports a formulation: the formulation imports this module and
registers its overloads beside the kernel that calls :func:`alpha_step`.

* ``model_start(model, step)``: the start of the step's iteration (the predicted
  accelerations and the coordinates and rates they give, the prescribed coordinates at
  the step's end).
* ``model_residual(model, step)``: evaluate the residual at the iterate.
* ``model_factorize(model, step) -> bool``: form and factorise the iteration matrix at
  the iterate (False: singular).
* ``model_solve(model, step)``: the Newton correction ``d`` of the last residual into the
  model's own vector.
* ``model_correct(model, step) -> float``: add ``d`` to a, abar, v and q; the size of the
  correction in the model's convergence norm (not finite: the iteration failed).

**Policy** (:class:`NewtonPolicy`): the matrix is formed at the first iterate, kept for
``full_after`` iterations (modified Newton), then formed at every iterate (full Newton),
``max_iter`` iterations in all; the iteration has converged when the correction's norm
is below ``tol``.
"""

from __future__ import annotations

import math
from typing import Callable, NamedTuple

from numba import types
from numba.core.extending import overload

from ..jit.kernel_cache import njit


class NewtonPolicy(NamedTuple):
    """How :func:`alpha_step` iterates (module docstring)."""

    max_iter: int        #: iterations in all
    full_after: int      #: iterations after which every iteration refactorises (>= max_iter: never)
    tol: float           #: the convergence tolerance, in the model's correction norm


def _protocol(name: str) -> Callable:
    """A function of the protocol: a name for the formulations' overloads (no Python body)."""
    def stub(model, step):
        raise NotImplementedError(f"{name} is compiled code only: a formulation overloads it for its model "
                                  f"({type(model).__name__})")
    stub.__name__ = stub.__qualname__ = name
    return stub


def overload_for(function: Callable, model_class: type) -> Callable:
    """Decorator: the decorated Python function is ``function``'s implementation (one of
    the protocol's) for models of the NamedTuple class ``model_class``; compiled into the
    calling kernel (inlined)."""
    def register(impl):
        @overload(function, inline="always")
        def typed(model, step):
            if isinstance(model, types.BaseNamedTuple) and model.instance_class is model_class:
                return impl
            return None
        return impl
    return register


model_start = _protocol("model_start")
model_residual = _protocol("model_residual")
model_factorize = _protocol("model_factorize")
model_solve = _protocol("model_solve")
model_correct = _protocol("model_correct")


@njit(cache=True, inline="always")
def alpha_step(model, step, policy: NewtonPolicy) -> bool:
    """Newton's iteration for one generalised-alpha step of ``model`` (module docstring):
    whether it converged (the iterate is then the step's end)."""
    model_start(model, step)
    for it in range(policy.max_iter):
        model_residual(model, step)
        if it == 0 or it >= policy.full_after:
            if not model_factorize(model, step):
                return False
        model_solve(model, step)
        dnorm = model_correct(model, step)
        if not math.isfinite(dnorm):
            return False
        if dnorm < policy.tol:
            return True
    return False
