"""mollify: exact smoothing kernels, evaluated in double precision.

    >>> import mollify, numpy as np
    >>> w = mollify.kernel("wendland:k=2", 3)          # Wendland C4 in 3D, support h
    >>> w.value(np.linspace(0, 1, 5), 0.5)             # W_h(r), r and h broadcast
    >>> mollify.exact.value("wendland:k=2", 3, "1/3")  # the exact value (fractions.Fraction, or a closed form)
    >>> mollify.verify(my_w, "wendland:k=2", 3)        # someone's kernel against the exact one

The kernels are libmollify's run-time form (C++, compiled into mollify._core);
errors are mollify.Error, a ValueError carrying the library's message.
"""

from . import _core
from . import exact
from ._core import Diagnosis, Error, Kernel, Report, isa
from ._verify import compare, samples, verify

__all__ = ["Error", "Kernel", "kernel", "exact", "isa", "verify", "samples", "compare", "Report", "Diagnosis"]


def kernel(spec, dim, precision="accurate"):
    """The kernel of a spec (any spelling of mollify's grammar) in dim dimensions.

    From the catalogue compiled into the library where it is there, else
    generated exactly, certified and cached on disk (mollify.exact.kernel).
    precision: "accurate" (double-double inside, <= 4 ulp) or "fast" (plain
    double). The Kernel evaluates every quantity over NumPy arrays: value, dr,
    d2r, laplacian, grad_over_r, hess_radial, potential, dpotential (= force),
    dpotential_over_r, potential_hess_radial at (r, h); gradient, pair,
    hessian, potential_gradient, potential_hessian at displacements (..., D).
    """
    return _core.kernel(spec, dim, precision)
