# mollify.verify: a kernel written in Python against the exact one
# (<mollify/verify.hpp>: hard points and seeded uniform points, MPFR
# references, the diagnosis). mollify's own kernels pass at <= 1 ulp (W,
# W'; potentials <= 4, see below) through a Python callable; kernels built wrong
# in each way are caught with the right diagnosis; the callable is called
# once on arrays when it takes them, else per point.
import math

import numpy as np
import pytest

import mollify

# Fewer uniform points than the default 10,000 where the test needs no more:
# the hard points (0, tiny r, breakpoints, the edge, tiny and huge h) are always there.
FEW = 500


@pytest.mark.parametrize("spec,dim,quantity", [
    ("wendland:k=2", 3, "value"), ("wendland:k=2", 3, "dr"), ("wendland:k=2", 3, "potential"),
    ("wendland:k=2", 3, "force"), ("cubic-spline", 2, "value"), ("cubic-spline", 1, "dr"),
    ("combo:m=3,base=wendland:k=2", 3, "value"), ("wendland:k=2", 3, "grad_over_r"),
])
def test_mollifys_own_kernels_pass_within_one_ulp(spec, dim, quantity):
    k = mollify.kernel(spec, dim)
    name = {"force": "dpotential"}.get(quantity, quantity)
    # W and W' within 1 ulp (measured <= 0.51); potentials within 4: outside
    # the support they are the Green's function -1/(4 pi r) and its
    # derivative, a few plain roundings (accuracy_test.cpp: raw <= 3.39).
    bound = 4 if quantity in ("potential", "force") else 1
    report = mollify.verify(lambda r, h: k.evaluate(name, r, h), spec, dim, quantity, ulps=bound)
    assert report.passed, str(report)
    assert report.max_ulps <= bound and report.points >= 10000 and report.diagnosis is None
    assert report.spec == spec and report.dim == dim and report.quantity == quantity
    assert "PASSED" in str(report)


def test_scalar_code_is_called_per_point_with_the_same_verdict():
    k = mollify.kernel("wendland:k=2", 3)
    calls = []

    def scalar(r, h):  # math.sqrt and `if` take no arrays
        calls.append(r)
        if r >= h:
            return 0.0
        return k.value(math.sqrt(r * r), h)

    report = mollify.verify(scalar, "wendland:k=2", 3, uniform=FEW)
    vectorised = mollify.verify(lambda r, h: k.value(r, h), "wendland:k=2", 3, uniform=FEW)
    assert report.passed and report.points == vectorised.points == len(calls) - 1  # the first call had the arrays
    assert report.max_ulps == vectorised.max_ulps


def with_kind(report, kind):
    assert not report.passed, str(report)
    assert report.diagnosis is not None and report.diagnosis.kind == kind, str(report)
    return report


def test_a_constant_off_by_one_part_in_a_million_is_a_constant_factor():
    k = mollify.kernel("wendland:k=2", 3)
    r = with_kind(mollify.verify(lambda r, h: (1 + 1e-6) * k.value(r, h), "wendland:k=2", 3, uniform=FEW),
                  "constant factor")
    assert r.max_ulps > 1e6 and r.worst[0].ulps == r.max_ulps


def test_a_factor_two_in_h_is_a_support_convention():
    k = mollify.kernel("wendland:k=2", 3)
    with_kind(mollify.verify(lambda r, h: k.value(r, 2 * h), "wendland:k=2", 3, uniform=FEW), "support convention")


def test_a_gradient_of_the_wrong_sign():
    k = mollify.kernel("cubic-spline", 3)
    with_kind(mollify.verify(lambda r, h: -k.dr(r, h), "cubic-spline", 3, "dr", uniform=FEW), "wrong sign")


def test_a_gradient_missing_a_factor_q():
    k = mollify.kernel("wendland:k=2", 3)
    with_kind(mollify.verify(lambda r, h: np.where(r > 0, k.dr(r, h) * h / np.maximum(r, 1e-300), 0.0),
                             "wendland:k=2", 3, "dr", uniform=FEW), "gradient factor")


def test_another_dimensions_kernel():
    k2 = mollify.kernel("wendland:k=2", 2)
    with_kind(mollify.verify(lambda r, h: k2.value(r, h), "wendland:k=2", 3, uniform=FEW), "other dimension")


def test_single_precision():
    k = mollify.kernel("wendland:k=2", 3)
    with_kind(mollify.verify(lambda r, h: k.value(r, h).astype(np.float32).astype(np.float64), "wendland:k=2", 3,
                             uniform=FEW), "single precision")


def test_samples_and_compare_are_the_two_halves():
    k = mollify.kernel("wendland:k=2", 3)
    r, h = mollify.samples("wendland:k=2", 3, uniform=FEW)
    assert r.dtype == np.float64 and r.shape == h.shape and len(r) > FEW
    report = mollify.compare("wendland:k=2", 3, r, h, k.value(r, h))
    assert report.passed and report.points == len(r)
    assert report.complete and report.hard_points_compared == report.hard_points > 100
    # the uniform points alone: passed, on those points only
    mine = mollify.compare("wendland:k=2", 3, r[-FEW:], h[-FEW:], k.value(r[-FEW:], h[-FEW:]))
    assert mine.passed and not mine.complete and mine.hard_points_compared == 0
    assert mine.hard_points == report.hard_points
    assert "on the given samples only (0 of" in str(mine) and "hard points" in repr(mine)
    with pytest.raises(mollify.Error, match="values"):
        mollify.compare("wendland:k=2", 3, r, h, k.value(r, h)[:-1])


def test_errors_name_the_bad_value():
    k = mollify.kernel("wendland:k=2", 3)

    def broken(r, h):
        if r > 0.5 * h:
            raise RuntimeError("out of table")
        return k.value(r, h)

    with pytest.raises(mollify.Error, match=r"broken\(r=.*h=.*RuntimeError: out of table"):
        mollify.verify(broken, "wendland:k=2", 3, uniform=FEW)
    # A call on arrays that gives no value per point is named with its shape, before the
    # per-point call's own failure (that alone had hidden what went wrong).

    def one_column(r, h):
        return k.value(r, h)[:, None]

    with pytest.raises(mollify.Error, match=r"one_column on arrays of \d+ points returned shape \(\d+, 1\), not \(\d+,\); "
                                            r"one_column\(r=0.0, h=1.0\) raised TypeError"):
        mollify.verify(one_column, "wendland:k=2", 3, uniform=FEW)
    with pytest.raises(mollify.Error, match="speed"):
        mollify.verify(k.value, "wendland:k=2", 3, quantity="speed")
    with pytest.raises(mollify.Error, match="nonesuch"):
        mollify.verify(k.value, "wendland:k=2", 3, convention="nonesuch")
    with pytest.raises(mollify.Error, match="k=99"):
        mollify.verify(k.value, "wendland:k=99", 3)
    # counts: named (pybind11 alone had raised a TypeError listing the signature)
    with pytest.raises(mollify.Error, match=r"uniform = -1: an integer >= 0"):
        mollify.samples("wendland:k=2", 3, uniform=-1)
    with pytest.raises(mollify.Error, match=r"uniform = 2.5"):
        mollify.verify(k.value, "wendland:k=2", 3, uniform=2.5)
    with pytest.raises(mollify.Error, match=r"seed = -3"):
        mollify.compare("wendland:k=2", 3, [0.5], [1.0], [k.value(0.5, 1.0)], seed=-3)
    with pytest.raises(mollify.Error, match=r"100000000000 uniform points: at most 100000000"):
        mollify.samples("wendland:k=2", 3, uniform=10**11)
