"""mollify.verify: someone's kernel, written in Python, against the exact one."""

import numpy as np

from . import _core

__all__ = ["verify", "samples", "compare"]

QUANTITIES = ("value", "dr", "potential", "force", "grad_over_r")


def _counts(seed, uniform):
    """seed and uniform as the library's unsigned integers, or mollify.Error
    naming the bad one (pybind11 would refuse -1 with a TypeError listing the
    signature; the library itself names a count above its limit)."""
    for name, v, top in (("seed", seed, 2**64), ("uniform", uniform, 2**64)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 0 <= v < top:
            raise _core.Error(f"{name} = {v!r}: an integer >= 0 is needed")
    return int(seed), int(uniform)


def samples(spec, dim, quantity="value", convention="cpp", ulps=4, seed=1, uniform=10000):
    """The arguments (r, h) to evaluate a kernel at (two float64 arrays): the
    hard points (0 and tiny r, the breakpoints, near and at the support edge,
    tiny and huge h) and `uniform` seeded uniform points, in the convention's
    units (mollify::verify::samples)."""
    seed, uniform = _counts(seed, uniform)
    return _core.verify_samples(spec, dim, quantity, convention, ulps, seed, uniform)


def compare(spec, dim, r, h, values, quantity="value", convention="cpp", ulps=4, seed=1, uniform=10000):
    """Values someone computed at (r, h), judged against the exact kernel: a
    Report. Any points may be given; the report counts the hard points among
    them (.hard_points_compared of .hard_points; .complete when all are), and
    a verdict on fewer than all holds for the given points only."""
    seed, uniform = _counts(seed, uniform)
    return _core.verify_compare(spec, dim, quantity, r, h, values, convention, ulps, seed, uniform)


def _evaluate(f, r, h):
    """f over the arrays in one call where it takes arrays (NumPy code), else
    once per point (scalar code: math.sqrt, `if q < 1`)."""
    name = getattr(f, "__name__", repr(f))
    on_arrays = ""  # what the call on arrays gave, where it gave no value per point
    try:
        with np.errstate(all="ignore"):
            got = np.asarray(f(r, h), dtype=np.float64)
        if got.shape == r.shape:
            return got
        on_arrays = f"{name} on arrays of {r.size} points returned shape {got.shape}, not ({r.size},); "
    except Exception:  # noqa: BLE001 -- any failure on arrays means: call it per point
        pass
    got = np.empty_like(r)
    for i, (ri, hi) in enumerate(zip(r.tolist(), h.tolist())):
        try:
            got[i] = float(f(ri, hi))
        except Exception as e:
            raise _core.Error(f"{on_arrays}{name}(r={ri!r}, h={hi!r}) raised {type(e).__name__}: {e}") from e
    return got


def verify(f, spec, dim, quantity="value", convention="cpp", ulps=4, seed=1, uniform=10000):
    """Checks f(r, h) against the exact kernel `spec` in `dim` dimensions.

    quantity: "value" (W_h(r)), "dr" (dW_h/dr), "potential" (phi_h(r)),
    "force" (dphi_h/dr) or "grad_over_r" ((dW_h/dr)/r, its limit at r = 0),
    in the convention's units: "cpp" (mollify: h is the
    support radius), "phantom", "swift", "gadget4" (their h and normalisation,
    generator/conventions.*). f is called once on NumPy arrays of all the
    sample points when it takes arrays, else once per point.

    Returns a Report: .passed (max error within `ulps`), .max_ulps, .rms_ulps,
    .worst (points: r, h, got, exact, ulps), .diagnosis (kind and text when
    the error is systematic: a constant factor such as 3/(359 pi) for
    1/(120 pi), a support convention, a gradient off by q, a wrong sign,
    another dimension's kernel, cancellation near the edge, single
    precision); str(report) is the table `mollify verify` prints.
    """
    r, h = samples(spec, dim, quantity, convention, ulps, seed, uniform)
    return compare(spec, dim, r, h, _evaluate(f, r, h), quantity, convention, ulps, seed, uniform)
