# mollify.kernel against exact values (mollify.exact.value: the generator's
# GMP rationals, or MPFR with Ziv's loop for closed forms with sqrt, arcsech,
# log), at the hard points: r = 0 and tiny r, the breakpoints, just inside
# the support edge down to 1 - r/h = 2^-52, the edge, outside; h tiny, huge
# and not a power of two. Bounds (ulps of the exact value, values below
# 1e-10 of the largest in ulps of the largest) are accuracy_test.cpp's for
# Precision::accurate: 4 for W and its derivatives (measured <= 0.51, the
# missing Wendland functions <= 2.96), 8 for potentials (<= 3.39, the Green's
# function's few plain roundings outside), 256 for a combination's second
# derivatives within one ulp of a breakpoint (the piece is chosen by the
# rounded r/h: accuracy_test.cpp says why).
import zlib
from fractions import Fraction

import numpy as np
import pytest

import mollify
from conftest import ulps

QUANTITIES = ["value", "dr", "d2r", "laplacian", "grad_over_r", "hess_radial",
              "potential", "dpotential", "dpotential_over_r", "potential_hess_radial"]
KINKS = {"d2r", "laplacian", "hess_radial"}

# (spec, dim, breakpoints in units of h)
KERNELS = [
    ("wendland:k=2", 3, []),
    ("cubic-spline", 1, [0.5]),
    ("cubic-spline", 2, [0.5]),
    ("mollifier:M=4,order=4", 2, []),
    ("wendland-missing:k=1,l=1", 3, []),
    ("combo:m=3,base=wendland:k=2", 3, [1 / 3, 2 / 3]),
    ("wendland:k=6,l=3", 3, []),  # not in the catalogue: generated, certified, cached
]

# r/h: 0, tiny, interior, near the edge (1 - 2^-k), the edge, outside.
U = [0.0, 2.0**-40, 2.0**-10, 0.3, 0.7, 1 - 2.0**-10, 1 - 2.0**-30, 1 - 2.0**-52, 1.0, 1 + 2.0**-52, 1.5, 3.0]
H = [1.0, 2.0**-120, 2.0**120, 0.375]


def bound(spec, quantity):
    if quantity.startswith("potential") or quantity.startswith("dpotential"):
        return 8
    if spec.startswith("combo") and quantity in KINKS:
        return 256
    return 4


def exact_double(spec, dim, r, quantity, h):
    """The exact value correctly rounded; infinity where the quantity is
    singular (the Hessian part (W'' - W'/r)/r^2 at r = 0 of a kernel whose
    third derivative at 0 is not 0), where the runtime returns infinity too."""
    try:
        v = mollify.exact.value(spec, dim, Fraction(r), quantity, h=Fraction(h))
    except mollify.Error as e:
        if "singular" not in str(e):
            raise
        return np.inf
    return float(v)


@pytest.mark.parametrize("spec,dim,breaks", KERNELS, ids=[f"{s} D{d}" for s, d, _ in KERNELS])
def test_every_quantity_at_the_hard_points(spec, dim, breaks):
    k = mollify.kernel(spec, dim)
    quantities = [q for q in QUANTITIES if k.has_potential or not q.startswith(("potential", "dpotential"))]
    us = sorted(set(U + breaks + [np.nextafter(b, 0) for b in breaks] + [np.nextafter(b, 2) for b in breaks]))
    for h in H:
        r = np.array([u * h for u in us])
        for q in quantities:
            got = getattr(k, q)(r, h)
            exact = np.array([exact_double(spec, dim, ri, q, h) for ri in r])
            singular = np.isinf(exact)
            assert np.all(np.isinf(got[singular])), f"{spec} D{dim} {q} h={h!r}: finite where singular"
            got, exact, r = got[~singular], exact[~singular], r[~singular]
            scale = 1e-10 * np.max(np.abs(exact))
            err = ulps(got, exact, scale)
            worst = int(np.argmax(err))
            assert err[worst] <= bound(spec, q), (
                f"{spec} D{dim} {q} h={h!r}: {err[worst]:.3g} ulp at r={r[worst]!r}: got {got[worst]!r}, "
                f"exact {exact[worst]!r}")


def test_outside_the_support_w_is_zero_and_the_potential_is_greens_function():
    k = mollify.kernel("wendland:k=2", 3)
    r = np.array([1.0, 1.5, 100.0])
    assert np.all(k.value(r, 1.0) == 0) and np.all(k.dr(r, 1.0) == 0)
    # -1/(4 pi r), correctly rounded by the exact module (a closed form in pi).
    exact = [float(mollify.exact.value("wendland:k=2", 3, Fraction(x), "potential")) for x in r]
    assert np.all(ulps(k.potential(r, 1.0), exact) <= 8)


def test_generated_kernel_is_cached(tmp_path):
    k = mollify.exact.kernel("wendland:k=5,l=2", 2, cache_dir=tmp_path)
    assert k.spec == "wendland:k=5,l=2" and k.dim == 2
    assert list(tmp_path.rglob("*.table")), "the generated table was not cached"
    again = mollify.exact.kernel("wendland:k=5,l=2", 2, cache_dir=tmp_path)
    r = np.linspace(0, 1, 101)
    assert np.array_equal(k.value(r, 1.0), again.value(r, 1.0))
    # The file's last line is zlib's CRC-32 of everything before it (format 4): another
    # program checks a table file with its own zlib, as TableFile::load checks it.
    [table] = tmp_path.rglob("*.table")
    text = table.read_bytes()
    body, last = text[:text.rindex(b"checksum ")], text[text.rindex(b"checksum "):]
    assert text.startswith(b"mollify-table 4\n") and body.endswith(b"\nend\n")
    assert last == b"checksum crc32 %08x\n" % zlib.crc32(body)


def test_fast_precision_is_the_same_kernel_within_its_bound():
    # Precision::fast: the power n multiplies the half-ulp rounding of 1 - q
    # (n = 6 here: <= ~4 ulp near the edge, precision.hpp says up to ~25 for n = 14).
    k = mollify.kernel("wendland:k=2", 3, precision="fast")
    assert k.precision == "fast" and k.with_precision("accurate").precision == "accurate"
    r = np.linspace(0, 1, 257)
    exact = np.array([exact_double("wendland:k=2", 3, x, "value", 1.0) for x in r])
    assert np.max(ulps(k.value(r, 1.0), exact, 1e-10 * exact.max())) <= 32


# --- broadcasting and shapes -------------------------------------------------

def test_broadcasting_r_and_h():
    k = mollify.kernel("cubic-spline", 3)
    r = np.linspace(0, 2, 7)[:, None]
    h = np.array([0.5, 1.0, 3.0])
    got = k.value(r, h)
    assert got.shape == (7, 3) and got.dtype == np.float64
    for i in range(7):
        for j in range(3):
            assert got[i, j] == k.value(float(r[i, 0]), float(h[j]))
    assert isinstance(k.value(0.5, 1.0), float)
    assert k.evaluate("dr", [0.1, 0.2], 1) .shape == (2,)
    assert np.array_equal(k("laplacian", r, h), k.laplacian(r, h))
    assert np.array_equal(k.force(r, h), k.dpotential(r, h))
    # Integers and non-contiguous views are taken as float64.
    assert k.value(np.arange(3)[::2], 2) .shape == (2,)
    with pytest.raises(ValueError, match="broadcast"):
        k.value(np.zeros(3), np.ones(4))


def test_vector_forms_are_the_radial_quantities_times_x():
    k = mollify.kernel("wendland:k=2", 3)
    rng = np.random.default_rng(7)
    x = rng.uniform(-1, 1, size=(50, 3))
    h = 1.25
    r = np.sqrt(np.sum(x * x, axis=1))
    w, g = k.pair(x, h)
    assert w.shape == (50,) and g.shape == (50, 3)
    # |x| is rounded here and in the runtime, perhaps differently (FMA):
    # within 1 ulp of the radial value plus |W'| times 2 ulp of r.
    slack = np.abs(k.dr(r, h)) * 2 * np.spacing(r) + np.spacing(np.abs(w))
    assert np.all(np.abs(w - k.value(r, h)) <= slack)
    assert np.max(np.abs(g - k.grad_over_r(r, h)[:, None] * x)) <= 4e-16 * np.max(np.abs(g))
    assert np.array_equal(k.gradient(x, h), g)
    H = k.hessian(x, h)
    assert H.shape == (50, 3, 3) and np.array_equal(H, np.swapaxes(H, 1, 2))
    trace = np.trace(H, axis1=1, axis2=2)
    lap = k.laplacian(r, h)
    assert np.max(np.abs(trace - lap)) <= 1e-13 * np.max(np.abs(lap))
    pg = k.potential_gradient(x, h)
    assert np.max(np.abs(pg - k.dpotential_over_r(r, h)[:, None] * x)) <= 4e-16 * np.max(np.abs(pg))
    assert k.potential_hessian(x, h).shape == (50, 3, 3)
    # One point, and h per point.
    assert k.gradient([0.1, 0.2, 0.3], 1.0).shape == (3,)
    assert k.pair(x, np.full(50, h))[0].shape == (50,)


def test_one_dimensional_displacements_and_the_cusp():
    k = mollify.kernel("cubic-spline", 1)
    x = np.array([-0.75, -0.25, 0.0, 0.25, 0.75])
    g = k.gradient(x, 1.0)
    assert g.shape == (5, 1)
    assert np.array_equal(g[:, 0], np.sign(x) * k.dr(np.abs(x), 1.0))
    assert k.hessian(x, 1.0).shape == (5, 1, 1)
    spiky = mollify.kernel("spiky", 3)
    assert np.array_equal(spiky.gradient(np.zeros(3), 1.0), np.zeros(3))  # W'(0) x/r at x = 0: 0, never NaN


# --- errors: mollify.Error, a ValueError with the runtime's message ----------

@pytest.mark.parametrize("call,named", [
    (lambda: mollify.kernel("wendland:k=99", 3), "99"),
    (lambda: mollify.kernel("nonsense", 3), "nonsense"),
    (lambda: mollify.kernel("wendland:k=2", 4), "4"),
    (lambda: mollify.kernel("viscosity", 1), "viscosity"),
    (lambda: mollify.kernel("wendland:k=2", 3, precision="exactish"), "exactish"),
    (lambda: mollify.kernel("wendland:k=2", 3).value(-1.0, 1.0), "-1"),
    (lambda: mollify.kernel("wendland:k=2", 3).value([0.5, float("nan")], 1.0), "nan"),
    (lambda: mollify.kernel("wendland:k=2", 3).value(0.5, 0.0), "h"),
    (lambda: mollify.kernel("wendland:k=2", 3).value(0.5, -2.0), "-2"),
    (lambda: mollify.kernel("wendland:k=2", 3).value(0.5, float("nan")), "nan"),
    (lambda: mollify.kernel("wendland:k=2", 3).value(0.5, 1e-300), "1e-300"),
    (lambda: mollify.kernel("wendland:k=2", 3).evaluate("speed", 0.5, 1.0), "unknown quantity 'speed' (known: value, dr, d2r, "),
    (lambda: mollify.kernel("box-d1", 1).potential(0.5, 1.0), "box-d1"),
    (lambda: mollify.kernel("wendland:k=2", 3).gradient(np.zeros((4, 2)), 1.0), "(4, 2)"),
    (lambda: mollify.kernel("wendland:k=2", 3).gradient([0.0, float("inf"), 0.0], 1.0), "inf"),
    (lambda: mollify.kernel("wendland:k=2", 3).hessian([0.0, float("nan"), 0.0], 1.0), "x[1] = nan"),
])
def test_errors_name_the_bad_value(call, named):
    with pytest.raises(mollify.Error) as e:
        call()
    assert isinstance(e.value, ValueError)
    assert named in str(e.value).lower() or named in str(e.value), str(e.value)
