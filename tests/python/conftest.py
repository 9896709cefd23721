# The tests of the Python package mollify (tests/python/, run by ctest as
# `python3 -m pytest` with Debian's interpreter and PYTHONPATH=build/python).
# A missing NumPy or pytest fails the ctest entry (an import error), never
# skips it.
import os
import tempfile

import numpy as np

# Kernels outside the catalogue are generated and cached: never into the
# user's ~/.cache from a test.
if "MOLLIFY_CACHE_DIR" not in os.environ:
    os.environ["MOLLIFY_CACHE_DIR"] = tempfile.mkdtemp(prefix="mollify-pytest-")


def ulps(got, exact, scale=0.0):
    """|got - exact| in ulps of max(|exact|, scale): accuracy_test.cpp's metric
    (values below 1e-10 of the largest are measured against it), with exact
    the correctly rounded reference (its own half ulp is part of the bound)."""
    got = np.asarray(got, dtype=float)
    exact = np.asarray(exact, dtype=float)
    ref = np.maximum(np.abs(exact), scale)
    err = np.abs(got - exact)
    with np.errstate(invalid="ignore", divide="ignore"):
        u = np.where(err == 0, 0.0, err / np.spacing(ref))
    return np.where(np.isfinite(got), u, np.inf)
