"""A user's test of their own integrator against the eulervop oracle: a classical RK4 in NumPy of
the SciML rigid body (y1' = -2 y2 y3, y2' = 1.25 y1 y3, y3' = -0.5 y1 y2 + 0.25 sin(t)^2), judged
at the scene's 101 sample times. Copy it into your suite and put your integrator in `integrate`.

Run: PYTHONPATH=build/python /usr/bin/python3 -m pytest -q examples/python
"""
import numpy as np

import eulervop

SCENE = eulervop.Scene.load(eulervop.problems()["sciml-rigid-body"])


def rhs(t, y, sign=1.0):
    return np.array([-2.0 * y[1] * y[2],
                     1.25 * y[0] * y[2],
                     -0.5 * y[0] * y[1] + sign * 0.25 * np.sin(t) ** 2])


def integrate(h=0.01, sign=1.0):
    """RK4 from t = 0 to 10, the state at every 0.1 (the scene's samples). `sign` = -1 plants a
    bug: the forcing with the wrong sign."""
    t, y = 0.0, np.array([1.0, 0.0, 0.9])
    times, states = [t], [y]
    for n in range(1, 1001):
        k1 = rhs(t, y, sign)
        k2 = rhs(t + h / 2, y + h / 2 * k1, sign)
        k3 = rhs(t + h / 2, y + h / 2 * k2, sign)
        k4 = rhs(t + h, y + h * k3, sign)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        t = n * h
        if n % 10 == 0:
            times.append(t)
            states.append(y)
    return np.array(times), np.array(states)


def test_rk4_is_within_its_error_bar():
    t, y = integrate()
    result = eulervop.check(SCENE, t, y, tol=1e-6)  # columns t, y1, y2, y3: the scene's form
    assert result.passed, result.as_dict()
    assert result.max_error < 1e-6


def test_a_planted_bug_fails():
    t, y = integrate(sign=-1.0)
    result = eulervop.check(SCENE, t, y, tol=1e-6)
    assert not result.passed
    assert result.as_dict()["exceeding_rows"] > 0
