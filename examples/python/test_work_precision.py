"""The work-precision study (work_precision.py) as a test: scipy's DOP853 on the SciML rigid body
against eulervop's certified reference, on a small ladder of tolerances, and a right-hand side
with a planted bug caught by a bar that the right one meets.

Run: PYTHONPATH=build/python /usr/bin/python3 -m pytest -q examples/python
"""
import math

import numpy as np
import pytest

import eulervop
import work_precision as wp

ORDER = 8  # DOP853 advances with Dormand and Prince's 8th-order weights
RTOLS = (1e-4, 1e-6, 1e-8, 1e-10)


@pytest.fixture(scope="module")
def ref():
    return wp.certified_reference("sciml-rigid-body")


@pytest.fixture(scope="module")
def dop853(ref):
    return wp.ladder(ref, "DOP853", RTOLS, repeats=1)


def test_errors_fall_with_the_tolerance(dop853):
    errors = [r.max_error for r in dop853]
    assert all(later < earlier for earlier, later in zip(errors, errors[1:])), errors
    assert all(r.calls == r.nfev for r in dop853)  # an explicit method: no Jacobian's calls


def test_errors_are_resolved_by_the_certified_radius(ref, dop853):
    # Each error is measured to +- the reference's radius (certified; about 1e-33 in quad): above
    # 1e4 radii, the 4 digits that work_precision.py prints are certain.
    radius = float(np.max(ref.radius))
    assert all(r.max_error > 1e4 * radius for r in dop853), (radius, dop853)


def test_the_observed_order(dop853):
    # Over a fixed span an order-p method's error goes as h^p ~ steps^-p once the steps are small
    # enough; over four rungs the step sizes' distribution still shifts with the tolerance, so
    # the fit is allowed one order either way: -9 < slope < -7 (measured -8.1). A 5(4) pair
    # (RK45: -4.8 on these rungs), or an 8th-order tableau miscoded to a lower order, fails it.
    s = wp.slope(dop853, "steps")
    assert -ORDER - 1 < s < -ORDER + 1, s
    # Against calls it is steeper (-9.4 here): the calls per accepted step fall as the steps
    # shrink (fewer rejected steps; fewer steps hold a sample and pay the dense output's 3).
    assert wp.slope(dop853, "calls") < s


def test_a_planted_bug_fails_a_bar_that_the_right_rhs_meets(ref):
    # 0.25*sin(t**2) for 0.25*sin(t)**2: a precedence slip in the forcing. The bar, 1e-7 at
    # rtol = 1e-9, is met by the right one with a margin of about 10 (its error is 8.7e-9).
    wrong = wp.rigid_body(forcing=lambda t: 0.25 * math.sin(t ** 2))
    for rhs, meets_the_bar in ((wp.rigid_body(), True), (wrong, False)):
        sol = wp.integrate(ref, "DOP853", 1e-9, rhs)
        result = eulervop.check(ref, sol.t, sol.y.T, tol=1e-7)
        assert result.passed == meets_the_bar, result.as_dict()
