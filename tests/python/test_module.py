"""The Python module against the program: the same values cell for cell, the same check
dictionary, errors as Python exceptions, two references at once, Ctrl-C."""
import csv
import json
from decimal import Decimal
from fractions import Fraction
import os
import signal
import subprocess
import threading

import numpy as np
import pytest

import eulervop


def cli_csv(binary, *args):
    """The rows of `eulervop reference ARGS` as (header, rows of cells), the metadata left out."""
    out = subprocess.run([binary, "reference", *args], check=True, capture_output=True, text=True).stdout
    lines = [l for l in out.splitlines() if l and not l.startswith("#")]
    rows = list(csv.reader(lines))
    return rows[0], rows[1:]


def exact_times(times):
    """--times with each float64's exact decimal (Decimal(float) is exact): the CLI then samples
    at the very binary numbers a Reference holds."""
    return ["--times", ",".join(str(Decimal(float(x))) for x in times)]


@pytest.mark.parametrize("scene,extra", [
    ("paper-fig1", ["--samples", "11"]),
    ("spacecraft-attitude", ["--samples", "7"]),
    ("sciml-rigid-body", []),
])
def test_reference_values_are_the_cli_cells(binary, scene, extra):
    path = eulervop.problems()[scene]
    samples = int(extra[1]) if extra else None
    ref = eulervop.reference(eulervop.Scene.load(path), samples=samples)
    # The scene's grid rounded to float64: each time the double nearest the CLI's decimal one.
    _, decimal_rows = cli_csv(binary, path, *extra)
    assert [float(r[0]) for r in decimal_rows] == list(ref.t)
    header, rows = cli_csv(binary, path, *exact_times(ref.t))
    assert ref.all_columns == header
    assert ref.decimal == rows
    assert ref.t.dtype == np.float64 and ref.t.shape == (len(rows),)
    assert ref.y.shape == (len(rows), len(ref.columns))
    assert "tau" not in ref.columns
    for k, name in enumerate(ref.columns):
        column = header.index(name)
        assert np.array_equal(ref.y[:, k], np.array([float(r[column]) for r in rows]))
    assert ref.meta["scene"] == scene
    assert ref.radius is None


def test_a_torque_of_the_attitude_is_the_cli_coupled_run(binary):
    path = eulervop.problems()["gravity-gradient-tumble"]
    ref = eulervop.reference(path, samples=7)
    header, rows = cli_csv(binary, path, *exact_times(ref.t))
    assert ref.decimal == rows
    assert ref.columns[:7] == ["omega1", "omega2", "omega3", "q0", "q1", "q2", "q3"]
    assert ref.meta["coupled"].startswith("the torque reads the attitude")
    assert float(ref.meta["q_norm_drift"]) < 1e-31
    cert = eulervop.reference(path, samples=7, certify=True)
    assert cert.radius_q is not None and cert.radius_q.max() < 1e-29
    with pytest.raises(ValueError, match="precision double"):
        eulervop.reference(path, samples=7, precision="double", certify=True)


def test_certify_gives_the_radius_of_q(binary):
    path = eulervop.problems()["pd-slew"]
    ref = eulervop.reference(path, samples=7, certify=True)
    header, rows = cli_csv(binary, path, *exact_times(ref.t), "--certify")
    assert ref.decimal == rows
    assert ref.radius_q is not None and ref.radius_q.shape == (7,)
    assert ref.radius_omega is not None and ref.radius.shape == (7,)
    # Each radius is its decimal rounded up to float64, so that it still bounds: the largest is
    # the double at or just above the header's figure.
    largest, text = ref.radius_q.max(), ref.meta["certified_max_error_q"]
    assert Fraction(float(largest)) >= Fraction(text) > Fraction(float(np.nextafter(largest, 0)))
    assert ref.radius_q.max() < 1e-29


def test_times_precision_and_certify(binary):
    path = eulervop.problems()["paper-fig1"]
    header, rows = cli_csv(binary, path, "--times", "0,0.5,1.25", "--precision", "mpfr:128", "--certify")
    ref = eulervop.reference(path, times=[0, 0.5, 1.25], precision="mpfr:128", certify=True)
    assert ref.decimal == rows
    assert ref.meta["precision"].startswith("mpfr:128")
    assert ref.radius is not None and ref.radius.shape == (3,)
    assert float(ref.meta["certified_max_error"]) >= ref.radius.max() * 0.99


def test_scene_from_toml_and_properties(root):
    text = (root / "data" / "scenes" / "spacecraft-physical.toml").read_text()
    s = eulervop.Scene.from_toml(text)
    assert s.name == "spacecraft-physical" and s.form == "physical" and s.text == text and s.path is None
    assert eulervop.Scene.load(eulervop.problems()["sciml-rigid-body"]).form == "coefficient"
    assert eulervop.Scene.load(eulervop.problems()["paper-fig1"]).form == "normalized"
    ref = eulervop.reference(s, samples=3)
    assert ref.columns[:3] == ["omega1", "omega2", "omega3"]


def test_check_is_the_cli_json(binary, tmp_path):
    scene = eulervop.problems()["spacecraft-attitude"]
    ref = eulervop.reference(scene, samples=13)
    y = ref.y.copy()
    y[:, 2] += 1e-7  # omega3
    traj = tmp_path / "traj.csv"
    with open(traj, "w") as f:
        # Each double's exact decimal (Decimal(float) is exact), which is how the module writes
        # arrays: the file and the arrays are the same numbers.
        f.write("t,omega1,omega2,omega3,q0,q1,q2,q3\n")
        for t, row in zip(ref.t, y):
            f.write(",".join(str(Decimal(float(x))) for x in [t, *row]) + "\n")
    flags = ["--tol", "2e-7", "--attitude-tol", "1e-6"]
    cli = subprocess.run([binary, "check", scene, str(traj), *flags, "--format", "json"],
                         capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    expected = json.loads(cli.stdout)
    expected["reference"].pop("seconds")  # the wall time of each run
    from_file = eulervop.check(scene, str(traj), tol=2e-7, attitude_tol=1e-6).as_dict()
    from_file["reference"].pop("seconds")
    assert from_file == expected
    from_arrays = eulervop.check(scene, ref.t, y, tol=2e-7, attitude_tol=1e-6)
    a = from_arrays.as_dict()
    a["reference"].pop("seconds")
    assert a.pop("trajectory") != expected.pop("trajectory")  # a scratch file, not traj.csv
    assert a == expected
    assert from_arrays.passed and from_arrays.verdict is True
    assert from_arrays.max_error == pytest.approx(1e-7, rel=1e-6)
    assert from_arrays.as_dict()["error_unit"] == "rad/s"
    failing = eulervop.check(ref, ref.t, y, tol=0.5e-7, attitude_tol=1e-6)
    assert not failing.passed and failing.exit_code == 1
    no_bar = eulervop.check(scene, ref.t, y, attitude_tol=None, tol=None)
    assert no_bar.verdict is None and not no_bar.passed


def test_bad_input_raises_value_error_with_the_cli_message(binary):
    with pytest.raises(ValueError, match="precision"):
        eulervop.reference(eulervop.problems()["paper-fig1"], precision="float80")
    with pytest.raises(ValueError, match="name"):
        eulervop.Scene.from_toml("name = 1\n")
    scene = eulervop.problems()["spacecraft-attitude"]
    ref = eulervop.reference(scene, samples=3)
    with pytest.raises(ValueError, match=r"attitude_tol: required, since y has q0\.\.q3 in y\[:, 3:7\]") as e:
        eulervop.check(scene, ref.t, ref.y, tol=1e-9)
    assert "attitude_tol=" in str(e.value) and "ignore_attitude=True" in str(e.value) and "--" not in str(e.value)
    with pytest.raises(ValueError, match="columns"):
        eulervop.check(scene, ref.t, ref.y, columns=["t", "omega1"], tol=1e-9)
    with pytest.raises(ValueError, match="missing.csv"):
        eulervop.check("missing.csv", ref.t, ref.y, tol=1e-9, attitude_tol=1e-9)
    with pytest.raises(ValueError, match="missing.toml"):
        eulervop.Scene.load("missing.toml")
    with pytest.raises(TypeError):
        eulervop.reference(42)


def test_numerical_failure_is_an_arithmetic_error(root):
    # Omega3 = 1e300 tau overflows double at tau = 1.798e8 (the scene the C++ tests share).
    overflow = (root / "tests" / "scenes" / "overflow.toml").read_text()
    with pytest.raises(eulervop.NumericalFailure, match="tau=") as failure:
        eulervop.reference(eulervop.Scene.from_toml(overflow))
    assert isinstance(failure.value, ArithmeticError)


def test_two_threads_run_two_references_at_once():
    scene = eulervop.problems()["spacecraft-attitude"]
    expected = eulervop.reference(scene, times=[0, 20000], t_end=20000).decimal
    results = [None, None]

    def work(i):
        results[i] = eulervop.reference(scene, times=[0, 20000], t_end=20000).decimal

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    # With the GIL released inside, this thread keeps running Python while both integrate.
    spins = 0
    while any(t.is_alive() for t in threads):
        spins += 1
    for t in threads:
        t.join()
    assert results[0] == expected and results[1] == expected
    assert spins > 1000


def test_ctrl_c_raises_keyboard_interrupt():
    scene = eulervop.problems()["spacecraft-attitude"]
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            eulervop.reference(scene, times=[0, 1.0e7], t_end=1.0e7)  # minutes if not interrupted
    finally:
        timer.cancel()


def test_docstrings_and_stubs(root):
    assert "reference(scene" in eulervop.reference.__doc__
    assert "check(against" in eulervop.check.__doc__
    for cls in (eulervop.Scene, eulervop.Reference, eulervop.CheckResult):
        assert cls.__doc__
    stub = os.path.join(os.path.dirname(eulervop.__file__), "eulervop.pyi")
    assert os.path.exists(stub)
