"""Exact values and any kernel of the grammar (mollify's exact generator: GMP, MPFR).

    >>> mollify.exact.value("wendland:k=0", 1, "1/3")         # rational: a Fraction
    Fraction(2, 3)
    >>> v = mollify.exact.value("wendland:k=2", 3, "1/3")     # a multiple of 1/pi: not a Fraction
    >>> v.closed_form, float(v)                               # ('12760/2187 * pi^-1', 1.8571715353018605)
"""

import decimal as _decimal
import numbers as _numbers
from fractions import Fraction

from . import _core
from ._core import ExactValue

__all__ = ["value", "kernel", "default_cache_dir", "ExactValue"]


def _rational(x, what):
    """x as the text of an exact rational: ints, Fractions, floats (their exact
    binary value), Decimals, and strings such as "1/3", "0.125", "1e-3"."""
    if isinstance(x, str):
        return x
    if isinstance(x, bool):
        raise TypeError(f"{what} must be a number, not a bool")
    if isinstance(x, (_numbers.Rational, float, _decimal.Decimal)) or hasattr(x, "__index__"):
        try:
            f = Fraction(x)
        except (ValueError, OverflowError) as e:  # NaN, infinity
            raise _core.Error(f"{what} = {x!r} is not a finite number") from e
        return f"{f.numerator}/{f.denominator}"
    if isinstance(x, _numbers.Real):  # e.g. numpy.float64
        return _rational(float(x), what)
    raise TypeError(f"{what} must be a rational number (int, Fraction, float or a string such as '1/3'), "
                    f"not {type(x).__name__}")


def value(spec, dim, r, quantity="value", h=1):
    """The exact value of a quantity of a kernel at radius r (and smoothing length h).

    r, h: exact rationals (int, Fraction, float, or a string "1/3", "0.125",
    or a hex-float "0x1.4cccccccccccdp-2", as `mollify-gen value --r` reads them).
    quantity: value, dr, d2r, laplacian, grad_over_r, hess_radial, potential,
    dpotential, dpotential_over_r, potential_hess_radial (scaled by h as the
    runtime scales them: f_h(r) = h^p f(r/h)); with h = 1 also the softening
    families of `mollify-gen value` (softening:n, d_soft:n, gfactor:n, dphidh).
    Returns a fractions.Fraction where the value is rational; otherwise an
    ExactValue: .closed_form (text), float(v) (correctly rounded),
    v.decimal(digits).
    """
    v = _core.exact_value(spec, dim, _rational(r, "r"), quantity, _rational(h, "h"))
    return Fraction(v.rational) if v.rational is not None else v


def kernel(spec, dim, precision="accurate", cache_dir=None, use_cache=True):
    """mollify::exact::kernel: the catalogue's kernel, else the cached table
    file, else generated now (certified) and cached in cache_dir
    (default: default_cache_dir())."""
    return _core.exact_kernel(spec, dim, precision, "" if cache_dir is None else str(cache_dir), use_cache)


def default_cache_dir():
    """$MOLLIFY_CACHE_DIR, else $XDG_CACHE_HOME/mollify, else ~/.cache/mollify."""
    return _core.default_cache_dir()
