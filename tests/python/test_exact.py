# mollify.exact.value: Fractions where the value is rational, closed forms
# and correct rounding otherwise; the same numbers as `mollify-gen value`
# (the same query code), and values derived here by hand from the kernels'
# definitions (README "Conventions": unit mass, support 1, Delta phi = W).
import math
import os
import subprocess
from fractions import Fraction

import numpy as np
import pytest

import mollify
from conftest import ulps


def test_rational_values_are_fractions():
    # Wendland psi_{1,0} = (1 - r)_+ has unit mass over R as it is.
    assert mollify.exact.value("wendland:k=0", 1, "1/3") == Fraction(2, 3)
    assert mollify.exact.value("wendland:k=0", 1, Fraction(1, 3)) == Fraction(2, 3)
    assert mollify.exact.value("wendland:k=0", 1, 0.25) == Fraction(3, 4)  # a float's exact binary value
    assert mollify.exact.value("wendland:k=0", 1, 2) == 0  # outside the support
    assert mollify.exact.value("wendland:k=0", 1, "1/3", "dr") == -1
    # Belley's box delta: 1/2 on [-1, 1]; its potential |r|/2 outside.
    assert mollify.exact.value("box", 1, 0) == Fraction(1, 2)
    assert mollify.exact.value("box", 1, 3, "potential") == Fraction(3, 2)
    assert type(mollify.exact.value("box", 1, 0)) is Fraction


def test_closed_forms_with_pi_round_correctly():
    # psi_{3,0} = (1 - r)^2: 4 pi int_0^1 (1 - r)^2 r^2 dr = 2 pi / 15, so W(0) = 15/(2 pi).
    v = mollify.exact.value("wendland:k=0", 3, 0)
    assert not isinstance(v, Fraction) and v.is_exact and v.rational is None
    assert "pi^-1" in v.closed_form and v.closed_form.startswith("15/2")
    assert ulps(float(v), 15 / (2 * math.pi)) <= 1
    assert v.decimal(20).startswith("2.38732414637843") and float(v.decimal(40)) == float(v)
    # 3D potential outside the support: the Green's function -1/(4 pi r).
    g = mollify.exact.value("wendland:k=2", 3, 4, "potential")
    assert g.closed_form == "-1/16 * pi^-1"


def test_closed_forms_beyond_rationals():
    # Missing Wendland functions: sqrt(1 - r^2) and arcsech r at rational r.
    v = mollify.exact.value("wendland-missing:k=1,l=1", 3, "1/3")
    assert not v.is_exact and "sqrt(8/9)" in v.closed_form
    k = mollify.kernel("wendland-missing:k=1,l=1", 3)
    assert ulps(k.value(1 / 3, 1.0), float(v)) <= 4
    # Every digits it accepts is delivered (past ~16,000 it had failed as "internal"); 0 and
    # 100001 are named.
    long = v.decimal(100000)
    assert len(long.split("e")[0].lstrip("-").replace(".", "")) == 100000
    assert long[:30] == v.decimal(40)[:30] and long.split("e")[1] == v.decimal(40).split("e")[1]
    for bad in (0, 100001):
        with pytest.raises(mollify.Error, match=f"digits {bad} is outside 1..100000"):
            v.decimal(bad)


def test_the_same_numbers_as_mollify_gen_value():
    gen = os.environ.get("MOLLIFY_GEN")
    if gen is None:
        pytest.fail("MOLLIFY_GEN (the mollify-gen command) is not set: run through ctest")
    for spec, dim, r, q in [("wendland:k=2", 3, "1/3", "value"), ("cubic-spline", 2, "1/2", "potential"),
                            ("wendland-missing:k=1,l=1", 3, "1/3", "dr"), ("wendland:k=2", 3, "1/5", "softening:3")]:
        out = subprocess.run([gen, "value", spec, "--dim", str(dim), "--r", r, "--quantity", q, "--digits", "30",
                              "--exact"], check=True, capture_output=True, text=True).stdout.splitlines()
        v = mollify._core.exact_value(spec, dim, r, q, "1")  # the object behind Fractions too
        assert [v.decimal(30), v.closed_form] == out, (spec, q)


def test_hex_floats_are_exact_as_in_mollify_gen_value():
    # A double's exact value: the hex-float string, the float itself and its Fraction agree;
    # its shortest decimal "0.325" is another rational (13/40) and another value.
    x = float.fromhex("0x1.4cccccccccccdp-2")
    for q in ("value", "dr"):
        by_hex = mollify.exact.value("wendland:k=2", 3, "0x1.4cccccccccccdp-2", q)
        assert by_hex.closed_form == mollify.exact.value("wendland:k=2", 3, x, q).closed_form
        assert by_hex.closed_form == mollify.exact.value("wendland:k=2", 3, Fraction(x), q).closed_form
        assert by_hex.closed_form != mollify.exact.value("wendland:k=2", 3, "0.325", q).closed_form
    assert mollify.exact.value("wendland:k=0", 1, "0x1p-1", h="0x1p+1") == mollify.exact.value("wendland:k=0", 1, "1/4") / 2
    with pytest.raises(mollify.Error, match="0x1p"):
        mollify.exact.value("wendland:k=0", 1, "0x1p")


def test_scaling_in_h():
    # f_h(r) = h^p f(r/h): W in 1D p = -1, W' p = -2, the potential p = +1.
    w = lambda r, q="value", h=1: mollify.exact.value("wendland:k=0", 1, r, q, h=h)
    assert w("1/2", h=2) == w("1/4") / 2
    assert w("1/2", "dr", h=2) == w("1/4", "dr") / 4
    assert w("1/2", "potential", h=2) == w("1/4", "potential") * 2
    # The 2D potential: phi(r/h) + log(h)/(2 pi), the Green's function log(r)/(2 pi) outside at every h.
    out = mollify.exact.value("wendland:k=2", 2, 6, "potential", h=2)
    assert out.closed_form == mollify.exact.value("wendland:k=2", 2, 6, "potential").closed_form
    assert "log(2)" in out.closed_form and "log(3)" in out.closed_form
    k = mollify.kernel("wendland:k=2", 2)
    for r, h in [(0.25, 2.0**-100), (0.75, 2.0**100), (0.0, 1e-44)]:
        e = mollify.exact.value("wendland:k=2", 2, r * h, "potential", h=h)
        assert ulps(k.potential(r * h, h), float(e)) <= 8


@pytest.mark.parametrize("call,named", [
    (lambda: mollify.exact.value("wendland:k=2", 3, -1), "-1"),
    (lambda: mollify.exact.value("wendland:k=2", 3, "1/0"), "1/0"),
    (lambda: mollify.exact.value("wendland:k=2", 3, "one third"), "one third"),
    (lambda: mollify.exact.value("wendland:k=2", 3, float("nan")), "nan"),
    (lambda: mollify.exact.value("wendland:k=2", 3, 0.5, h=0), "h = 0"),
    (lambda: mollify.exact.value("wendland:k=2", 3, 0.5, "speed"), "speed"),
    (lambda: mollify.exact.value("wendland:k=2", 3, 0.5, "softening:2", h=2), "softening:2"),
    (lambda: mollify.exact.value("wendland:k=99", 3, 0.5), "99"),
    (lambda: mollify.exact.value("spiky", 3, 0, "grad_over_r"), "singular"),
])
def test_errors_name_the_bad_value(call, named):
    with pytest.raises(ValueError) as e:
        call()
    assert named in str(e.value), str(e.value)


def test_non_numbers_are_type_errors():
    with pytest.raises(TypeError):
        mollify.exact.value("wendland:k=2", 3, [0.5])
