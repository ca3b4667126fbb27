"""The module as a user meets it: a physical gravity-gradient scene with rate damping, integrated
by a small NumPy RK4 of the rates and the quaternion, judged with `eulervop.check`. Its messages
name keywords, shapes and indices (never a flag of the CLI or a scratch file), a reference's
`y` is what `check` reads by default (so it judges itself with error ~0), and every float64 is
judged at its exact binary value."""
import math
import tempfile
from decimal import Decimal, localcontext
from fractions import Fraction

import numpy as np
import pytest

import eulervop

INERTIA = np.array([120.0, 80.0, 100.0])  # kg m^2, listed out of order, as in the TOML below
MEAN_MOTION = 0.0011                       # rad/s
DAMPING = 0.05                             # N m s: M = -DAMPING * omega
OMEGA0 = ["0.02", "-0.015", "0.01"]        # rad/s, the decimals of [initial] omega
Q0 = ["0.5", "0.5", "0.5", "0.5"]          # [initial] q, exactly 1 in norm

SCENE = eulervop.Scene.from_toml(f"""
name = "damped-gravity-gradient"
description = "A tumbling body under the gravity gradient of a circular orbit, its rates damped."

[body]
inertia = [120.0, 80.0, 100.0]

[torque]
M = ["-{DAMPING}*omega1", "-{DAMPING}*omega2", "-{DAMPING}*omega3"]

[torque.gravity_gradient]
mean_motion = {MEAN_MOTION}

[initial]
omega = [{", ".join(OMEGA0)}]
q = [{", ".join(Q0)}]

[span]
t_end = 600.0
samples = 61

[reference]
precision = "quad"
""")

# A scene without an attitude, for the messages about q0..q3.
RATES_ONLY = eulervop.Scene.from_toml("""
name = "rates-only"
[body]
inertia = [120.0, 80.0, 100.0]
[initial]
omega = [0.02, -0.015, 0.01]
[span]
t_end = 600.0
samples = 61
""")

NORMALIZED = eulervop.Scene.from_toml("""
name = "normalized-short"
[torque]
G = [0.001, 0.001, "0.001*cos(tau)"]
[initial]
Omega = [0.5, 0.0, 1.0]
[span]
tau_end = 20.0
samples = 21
""")

# y1' = -2 y2 y3 + 1, y2' = 1.25 y1 y3, y3' = -0.5 y1 y2 from y = (1, 0, 0): y2 and y3 stay 0,
# so the exact solution is y = (1 + t, 0, 0).
DRIFT = eulervop.Scene.from_toml("""
name = "uniform-drift"
[equations]
a = [-2.0, 1.25, -0.5]
[torque]
f = [1.0, 0.0, 0.0]
[initial]
y = [1.0, 0.0, 0.0]
[span]
t_end = 1.0
samples = 11
""")


# ---- the user's integrator -----------------------------------------------------------------------

def qmul(p, q):
    """Hamilton product, scalar first."""
    return np.concatenate(([p[0] * q[0] - p[1:] @ q[1:]], p[0] * q[1:] + q[0] * p[1:] + np.cross(p[1:], q[1:])))


def rhs(t, s, gravity_sign=1.0):
    """Euler's equations with damping and the gravity gradient (docs/attitude.md: r = (cos n t,
    sin n t, 0) inertial, r_b = R(q)^T r, M = 3 n^2 r_b x (I r_b)), and q' = 1/2 q (x) (0, omega).
    `gravity_sign` = -1 plants a bug: the gravity gradient with the wrong sign."""
    w, q = s[:3], s[3:]
    r = np.array([0.0, math.cos(MEAN_MOTION * t), math.sin(MEAN_MOTION * t), 0.0])
    b = qmul(qmul(q * [1, -1, -1, -1], r), q)[1:]  # q* r q: r in the body's axes
    m = -DAMPING * w + gravity_sign * 3 * MEAN_MOTION ** 2 * np.cross(b, INERTIA * b)
    dw = (m - np.cross(w, INERTIA * w)) / INERTIA
    dq = 0.5 * qmul(q, np.concatenate(([0.0], w)))
    return np.concatenate((dw, dq))


def integrate(gravity_sign=1.0, h=1.0):
    """Classical RK4 from t = 0 to 600 s; the state every 10 s (the scene's 61 samples)."""
    s = np.array([float(x) for x in OMEGA0 + Q0])
    times, states = [0.0], [s]
    for n in range(1, 601):
        t = (n - 1) * h
        k1 = rhs(t, s, gravity_sign)
        k2 = rhs(t + h / 2, s + h / 2 * k1, gravity_sign)
        k3 = rhs(t + h / 2, s + h / 2 * k2, gravity_sign)
        k4 = rhs(t + h, s + h * k3, gravity_sign)
        s = s + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        if n % 10 == 0:
            times.append(n * h)
            states.append(s)
    return np.array(times), np.array(states)


@pytest.fixture(scope="module")
def trajectory():
    return integrate()


@pytest.fixture(scope="module")
def ref():
    return eulervop.reference(SCENE)


def assert_in_python_terms(message):
    """No flag of the CLI and no scratch file: the user gave keywords and arrays."""
    assert "--" not in message, message
    assert "eulervop-py-" not in message and tempfile.gettempdir() not in message, message
    assert ".csv" not in message and ".toml" not in message, message


# ---- judged with the keywords ----------------------------------------------------------------------

def test_rk4_is_within_its_bars_and_a_planted_bug_is_not(trajectory):
    t, y = trajectory
    assert y.shape == (61, 7)
    # Bars about 10x above RK4's error at h = 1 s on this scene (measured with this check: 4.3e-13
    # rad/s and 2.2e-9 rad; at h = 0.5 s, 2.5e-14 and 9.6e-11, RK4's h^4). The planted bug is off
    # by 8e-5 rad/s and 1.4e-2 rad.
    result = eulervop.check(SCENE, t, y, tol=5e-12, attitude_tol=3e-8)
    d = result.as_dict()
    assert result.passed and result.exit_code == 0, d
    assert d["error_unit"] == "rad/s" and d["attitude_judged"] is True
    assert 1e-14 < result.max_error < 5e-12
    assert 1e-11 < d["max_attitude_error"] < 3e-8
    bug_t, bug_y = integrate(gravity_sign=-1.0)
    failing = eulervop.check(SCENE, bug_t, bug_y, tol=5e-12, attitude_tol=3e-8)
    assert not failing.passed and failing.exit_code == 1
    assert failing.as_dict()["exceeding_rows"] > 0


def test_the_wrong_orientation_names_the_shapes(trajectory):
    t, y = trajectory
    with pytest.raises(ValueError) as e:
        eulervop.check(SCENE, t, y.T, tol=1e-8, attitude_tol=2e-7)
    assert str(e.value) == "y has shape (7, 61); expected (61, m) with one row per time in t (transpose it?)"
    with pytest.raises(ValueError) as e:
        eulervop.check(SCENE, t[:, None], y, tol=1e-8, attitude_tol=2e-7)
    assert str(e.value) == "t has shape (61, 1); expected (n,), one time per row of y"


def test_without_the_attitude_bar_the_message_names_the_keywords(trajectory):
    t, y = trajectory
    with pytest.raises(ValueError) as e:
        eulervop.check(SCENE, t, y, tol=1e-8)
    message = str(e.value)
    assert_in_python_terms(message)
    assert message.startswith("attitude_tol: required, since y has q0..q3 in y[:, 3:7]")
    assert "attitude_tol=" in message and "ignore_attitude=True" in message
    # The alternative it names works: the rates alone, said so.
    rates = eulervop.check(SCENE, t, y, tol=1e-8, ignore_attitude=True)
    assert rates.passed and rates.as_dict()["attitude_judged"] is False


# ---- a reference judges itself -----------------------------------------------------------------

def test_a_physical_reference_round_trips(ref):
    assert ref.columns == ["omega1", "omega2", "omega3", "q0", "q1", "q2", "q3"]
    assert ref.y.shape == (61, 7)
    assert ref.normalized_columns == ["tau", "Omega1", "Omega2", "Omega3"]
    assert ref.normalized.shape == (61, 4)
    for k, name in enumerate(ref.normalized_columns):
        column = ref.all_columns.index(name)
        assert np.array_equal(ref.normalized[:, k], [float(row[column]) for row in ref.decimal])
    # Its cells rounded to double are within half an ulp of the quad values (|omega| < 0.03 rad/s,
    # |q| <= 1; the times are whole seconds, exact): errors of a few 1e-18 rad/s and, for the
    # angle between two quaternions each rounded by ~5e-17 per component, about 1e-16 rad.
    result = eulervop.check(SCENE, ref.t, ref.y, tol=1e-16, attitude_tol=1e-15)
    assert result.passed, result.as_dict()
    assert result.max_error < 1e-16 and result.as_dict()["max_attitude_error"] < 1e-15
    against_itself = eulervop.check(ref, ref.t, ref.y, tol=1e-16, attitude_tol=1e-15)
    assert against_itself.passed, against_itself.as_dict()
    # The normalized columns, named, are judged too (Eq. 20 in tau, Omega; tau is not exact in
    # double, so the bar allows the rates' change over half an ulp of tau as well).
    normalized = eulervop.check(SCENE, ref.normalized[:, 0], ref.normalized[:, 1:],
                                columns=ref.normalized_columns, tol=1e-14)
    assert normalized.passed, normalized.as_dict()


@pytest.mark.parametrize("scene,columns", [
    (NORMALIZED, ["Omega1", "Omega2", "Omega3"]),
    (DRIFT, ["y1", "y2", "y3"]),
])
def test_normalized_and_coefficient_references_round_trip(scene, columns):
    ref = eulervop.reference(scene)
    assert ref.columns == columns and ref.y.shape == (len(ref.t), 3)
    # |Omega| ~ 1 and |y| ~ 2: the cells rounded to double (and DRIFT's times k/10, which a double
    # does not hold exactly) move each row by about 1e-16 (measured: 5.6e-17 and 1.1e-16).
    result = eulervop.check(scene, ref.t, ref.y, tol=1e-14)
    assert result.passed, result.as_dict()
    assert result.max_error < 1e-14


# ---- exact binary values -------------------------------------------------------------------------

def exact_norm(differences):
    """The two-norm of exact rationals, to 50 digits."""
    with localcontext() as c:
        c.prec = 50
        return float(sum((Decimal(d.numerator) / Decimal(d.denominator)) ** 2 for d in differences).sqrt())


def test_values_are_judged_at_their_binary_values():
    # At t = 0 the reference is [initial] omega, the decimals 0.02, -0.015, 0.01 (to quad's
    # 1e-34 relative). The doubles nearest them are not those decimals, though each one's shortest
    # round-trip text is: written as that text, the row would be judged at error 0.
    omega = np.array([float(x) for x in OMEGA0])
    assert [repr(x) for x in omega] == OMEGA0
    row = np.concatenate((omega, [float(x) for x in Q0]))[None, :]
    expected = exact_norm([Fraction(x) - Fraction(d) for x, d in zip(omega, OMEGA0)])
    assert 1e-19 < expected < 1e-17
    result = eulervop.check(SCENE, np.array([0.0]), row, tol=1e-15, attitude_tol=1e-15)
    assert result.max_error == pytest.approx(expected, rel=1e-12, abs=0)


def test_times_are_judged_at_their_binary_values():
    # DRIFT's exact solution is y1 = 1 + t. At the double t = 0.1 the reference is 1 + 0.1000...0555
    # (0.1's binary value, exact in quad), and the double 1.1 differs from it by 8.3e-17; at the
    # decimal time "0.1", the shortest text of the same double, it would be judged at error 0.
    t = np.array([0.0, 0.1, 0.7])
    y = np.array([[1.0, 0.0, 0.0], [1.1, 0.0, 0.0], [1.7, 0.0, 0.0]])
    errors = [abs(Fraction(y1) - (1 + Fraction(ti))) for ti, y1 in zip(t, y[:, 0])]
    expected = float(max(errors))
    assert expected > 1e-17 and abs(Fraction(repr(1.1)) - (1 + Fraction(repr(0.1)))) == 0
    d = eulervop.check(DRIFT, t, y, tol=1e-15).as_dict()
    assert d["max_error"] == pytest.approx(expected, rel=1e-12, abs=0)
    assert d["max_error_time"] == t[int(np.argmax(errors))]


# ---- every message in the caller's terms ------------------------------------------------------------

def test_messages_name_keywords_shapes_and_indices(trajectory, ref):
    t, y = trajectory
    bad_t = t.copy()
    bad_t[2] = bad_t[1]
    nan_y = y.copy()
    nan_y[3, 1] = np.nan
    zero_q = y.copy()
    zero_q[4, 3:] = 0.0
    off_sample = t.copy()
    off_sample[1] = 15.0
    cases = [
        (lambda: eulervop.check(SCENE, t, y, tol=-1.0, attitude_tol=1e-6), "tol=-1.0: must be >= 0"),
        (lambda: eulervop.check(SCENE, t, y, rel_tol=math.nan, attitude_tol=1e-6), "rel_tol=nan: "),
        (lambda: eulervop.check(SCENE, t, y, attitude_tol=1e-6), "attitude_tol=1e-06: give tol= or rel_tol= too"),
        (lambda: eulervop.check(SCENE, t, y, tol=1e-8, attitude_tol=1e-6, ignore_attitude=True),
         "ignore_attitude=True: given with attitude_tol=1e-06 (give one of them)"),
        (lambda: eulervop.check(SCENE, t, y, tol=1e-8, attitude_tol=1e-6, precision="float80"),
         "precision='float80': expected double, quad or mpfr:BITS"),
        (lambda: eulervop.check(ref, t, y, tol=1e-8, attitude_tol=1e-6, precision="quad"),
         "precision='quad': not used with a reference file"),
        (lambda: eulervop.check(SCENE, t, y, tol=1e-8, attitude_tol=1e-6, scd_atol=0.0),
         "scd_atol=0.0: must be positive"),
        (lambda: eulervop.check(SCENE, t, y[:, :3], tol=1e-8, attitude_tol=1e-6),
         "attitude_tol=1e-06: y (shape (61, 3)) has no columns q0..q3 (no attitude to check)"),
        (lambda: eulervop.check(SCENE, t, y[:, :3], tol=1e-8, ignore_attitude=True),
         "ignore_attitude=True: y (shape (61, 3)) has no columns q0..q3"),
        (lambda: eulervop.check(SCENE, t, y[:, :4], tol=1e-8),
         "y has shape (61, 4); expected (61, 3), the rates omega1..3, or (61, 7), omega1..3 then q0..q3, "
         "for scene damped-gravity-gradient (physical form); or name y's columns with columns="),
        (lambda: eulervop.check(SCENE, t, y, columns=["t", "w1", "w2", "w3"], tol=1e-8),
         "columns has 4 names; expected 8: the time's, then one for each column of y (y has shape (61, 7))"),
        (lambda: eulervop.check(SCENE, t, y[:, :3], columns=["t", "omega1", "omega2", "w3"], tol=1e-8),
         "columns=['t', 'omega1', 'omega2', 'w3']: no column `omega3`"),
        (lambda: eulervop.check(SCENE, t, y[:, :3], columns=["t", "omega1", "omega2", "omega1"], tol=1e-8),
         "columns[3] = 'omega1': listed twice"),
        (lambda: eulervop.check(RATES_ONLY, t, y, tol=1e-8, attitude_tol=1e-6),
         "y has q0..q3 in y[:, 3:7], but scene rates-only has no attitude ([initial] q); give the rates alone"),
        (lambda: eulervop.check(SCENE, bad_t, y, tol=1e-8, attitude_tol=1e-6),
         "t[2] = 10.0 does not increase (t[1] = 10.0): the times must increase strictly"),
        (lambda: eulervop.check(SCENE, -t[::-1], y, tol=1e-8, attitude_tol=1e-6),
         "t[0] = -600.0 is negative (the reference starts at 0)"),
        (lambda: eulervop.check(SCENE, t, nan_y, tol=1e-8, attitude_tol=1e-6), "y[3, 1] = nan is not finite"),
        (lambda: eulervop.check(SCENE, t, zero_q, tol=1e-8, attitude_tol=1e-6),
         "y[4] has q0..q3 = 0 (y[:, 3:7]), which is no attitude"),
        (lambda: eulervop.check(SCENE, t[:0], y[:0], tol=1e-8, attitude_tol=1e-6),
         "t has shape (0,): give at least one time"),
        (lambda: eulervop.check(SCENE, t, None, tol=1e-8), "y: missing"),
        (lambda: eulervop.check(ref, off_sample, y, tol=1e-8, attitude_tol=1e-6),
         "t[1] = 15.0 is not a sample time of the Reference (ref.t); nearest: "),
        (lambda: eulervop.reference(SCENE, tau_end=5.0),
         "tau_end=5.0: scene damped-gravity-gradient is physical (has [body]); give t_end= in s"),
        (lambda: eulervop.reference(NORMALIZED, t_end=5.0), "t_end=5.0: scene normalized-short is normalized"),
        (lambda: eulervop.reference(SCENE, samples=1), "samples=1: must be a whole number"),
        (lambda: eulervop.reference(SCENE, samples=3, times=[0.0, 10.0]), "samples and times: give one or the other"),
        (lambda: eulervop.reference(SCENE, times=[0.0, 700.0]),
         "times[1] = 700.0 is beyond t_end = 600.0 of scene damped-gravity-gradient"),
        (lambda: eulervop.reference(SCENE, times=[[0.0, 10.0]]), "times has shape (1, 2); expected (k,)"),
        (lambda: eulervop.reference(SCENE, times=["a"]), "times: expected numbers, got ['a']"),
        (lambda: eulervop.check(SCENE, "times", y, tol=1e-8), "t: expected an array of numbers, got 'times'"),
        (lambda: eulervop.reference(SCENE, samples=3, precision="double", certify=True),
         "certify=True: precision double is not certified"),
    ]
    for call, expected in cases:
        with pytest.raises(ValueError) as e:
            call()
        message = str(e.value)
        assert message.startswith(expected), (expected, message)
        assert_in_python_terms(message)
