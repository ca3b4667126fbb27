"""The oracle as a test suite uses it: times are the float64 numbers the caller holds, a
Reference's rows are its own times exactly, names of shipped scenes work everywhere, a check
without a bar has no verdict, a wrong keyword is one line, and the module writes no file."""
import os
import subprocess
import sys
import warnings
from fractions import Fraction

import numpy as np
import pytest

import eulervop

SCIML_100 = "sciml-rigid-body-100"  # y1' = -2 y2 y3, y2' = 1.25 y1 y3, y3' = -0.5 y1 y2 + 0.25 sin(t)^2


def sciml_rhs(t, y):
    return np.array([-2.0 * y[1] * y[2], 1.25 * y[0] * y[2], -0.5 * y[0] * y[1] + 0.25 * np.sin(t) ** 2])


@pytest.fixture(scope="module")
def ref100():
    return eulervop.reference(SCIML_100)


def test_a_reference_judges_itself_to_its_cells_rounding(ref100):
    # ref.t are the float64 times the reference was computed at, and ref.y its values rounded to
    # nearest: each row is off by its rounding alone, at most half an ulp per component, so below
    # 2^-53 sqrt(3) |y| < 2e-16 |y|. The bar 1e-15 |y| (rel_tol) must hold at every row.
    assert ref100.t.dtype == np.float64 and len(ref100.t) == 1001
    against_scene = eulervop.check(SCIML_100, ref100.t, ref100.y, rel_tol=1e-15)
    assert against_scene.passed, against_scene.as_dict()
    against_itself = eulervop.check(ref100, ref100.t, ref100.y, rel_tol=1e-15)
    assert against_itself.passed, against_itself.as_dict()
    # Against itself the reference's own rows are the truth: the errors are y's rounding exactly.
    worst = max(float(abs(Fraction(c) - Fraction(float(c)))) for row in ref100.decimal[990:] for c in row[1:])
    assert 0 < worst < 2e-16 * 13


def test_a_time_is_judged_at_its_binary_value(ref100):
    # One time moved by one ulp, its row kept: against the scene the row is judged at the moved
    # time, so its error is the motion over one ulp, |y'(t)| ulp(t) (about 1e-13 at t = 98.9),
    # three orders above the rest; against the Reference the moved time is no sample of it.
    k = 989
    t = ref100.t.copy()
    t[k] = np.nextafter(t[k], np.inf)
    step = Fraction(float(t[k])) - Fraction(float(ref100.t[k]))
    expected = float(np.linalg.norm(sciml_rhs(ref100.t[k], ref100.y[k]))) * float(step)
    result = eulervop.check(SCIML_100, t, ref100.y, rel_tol=1e-15).as_dict()
    assert result["pass"] is False and result["exceeding_rows"] == 1
    assert result["max_error_time"] == t[k]
    assert result["max_error"] == pytest.approx(expected, rel=1e-3)
    with pytest.raises(ValueError, match=r"t\[989\] = 98\.9.* is not a sample time of the Reference \(ref\.t\)"):
        eulervop.check(ref100, t, ref100.y, rel_tol=1e-15)


def test_times_given_are_computed_at_exactly():
    # 0.1 is not a decimal in binary: the reference is computed at the double 0.1 itself, and
    # ref.t gives back the very numbers that went in.
    times = np.array([0.0, 0.1, 1.0 / 3.0, 0.7])
    ref = eulervop.reference("sciml-rigid-body", times=times)
    assert np.array_equal(ref.t, times)
    assert ref.meta["times"].startswith("binary64")
    assert ref.decimal[1][0] == "1.000000000000000055511151231257827021e-01"


def test_a_million_rows_cross_as_arrays():
    # A dense trajectory of the reference itself (no file, no text): the check passes with the
    # rounding bar, and a planted error in one row is found at its index.
    t = np.linspace(0.0, 10.0, 200001)
    ref = eulervop.reference("sciml-rigid-body", times=t)
    assert np.array_equal(ref.t, t)
    y = ref.y.copy()
    assert eulervop.check("sciml-rigid-body", t, y, rel_tol=1e-15).passed
    y[123456, 2] += 1e-9
    d = eulervop.check("sciml-rigid-body", t, y, rel_tol=1e-15).as_dict()
    assert d["exceeding_rows"] == 1 and d["max_error_time"] == t[123456]
    assert d["max_error"] == pytest.approx(1e-9, rel=1e-6)


def test_without_a_bar_there_is_no_verdict(ref100):
    result = eulervop.check(ref100, ref100.t, ref100.y)
    assert result.passed is None and result.verdict is None and result.exit_code == 0
    with pytest.raises(ValueError, match="no verdict"):
        bool(result)


def test_a_shipped_scene_is_taken_by_its_name(ref100):
    assert eulervop.Scene.load("sciml-rigid-body").name == "sciml-rigid-body"
    assert eulervop.Scene.load("sciml-rigid-body").path == eulervop.problems()["sciml-rigid-body"]
    assert eulervop.check("sciml-rigid-body-100", ref100.t, ref100.y, rel_tol=1e-15).passed
    with pytest.raises(ValueError) as e:
        eulervop.reference("sciml-rigid-bod")
    message = str(e.value)
    assert "\n" not in message and "sciml-rigid-body" in message and "shipped" in message


def test_a_wrong_keyword_is_one_line():
    with pytest.raises(TypeError) as e:
        eulervop.check("sciml-rigid-body", [0.0], [[1.0, 0.0, 0.9]], tolerance=1e-8)
    assert str(e.value).startswith("check(): no keyword tolerance=; did you mean tol=?")
    assert "\n" not in str(e.value)
    with pytest.raises(TypeError) as e:
        eulervop.reference("sciml-rigid-body", samples=2.5)
    assert str(e.value) == "reference(): samples=2.5: expected an int or None"
    with pytest.raises(TypeError, match=r"^reference\(\): scene is missing"):
        eulervop.reference()
    # A right call still takes integers where floats are due.
    assert eulervop.check("sciml-rigid-body", [0], [[1, 0, 0.9]], tol=1).passed


def test_scenes_from_dicts_and_templates():
    scene = eulervop.Scene.load("sciml-rigid-body")
    d = scene.as_dict()
    assert d["equations"]["a"] == [-2.0, 1.25, -0.5]
    d["span"]["t_end"] = 2.0
    d["name"] = "sciml-to-2"
    shorter = eulervop.Scene.from_dict(d)
    assert shorter.name == "sciml-to-2" and shorter.form == "coefficient"
    # The first two seconds are the same problem: the same numbers where both have samples, to the
    # quad reference's accuracy (the runs' last segments end apart, at 2 and at 10).
    a = eulervop.reference(scene, times=[0.0, 1.0, 2.0])
    b = eulervop.reference(shorter, times=[0.0, 1.0, 2.0])
    for row_a, row_b in zip(a.decimal, b.decimal):
        assert max(abs(Fraction(x) - Fraction(y)) for x, y in zip(row_a, row_b)) < Fraction(1, 10**31)
    for form in ("normalized", "physical", "coefficient"):
        template = eulervop.Scene.from_toml(eulervop.scene_template(form))
        assert template.form == form
    with pytest.raises(ValueError, match="form `bogus`"):
        eulervop.scene_template("bogus")
    with pytest.raises(ValueError, match=r"span\.t_end = .*not a TOML value"):
        eulervop.Scene.from_dict({"span": {"t_end": object()}})


def test_a_run_of_years_is_announced():
    # 1e12 time units would take years: after a couple of seconds a warning gives the estimate
    # (made an error here, which stops the run).
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        with pytest.raises(RuntimeWarning, match=r"about .* in all at this pace"):
            eulervop.reference("sciml-rigid-body", t_end=1e12, times=[0.0, 1e12])


def test_the_module_writes_no_file(tmp_path):
    # With TMPDIR pointing nowhere, a reference, a check of arrays and a certificate still run.
    code = """
import eulervop, numpy as np
ref = eulervop.reference("sciml-rigid-body", certify=True)
assert eulervop.check("sciml-rigid-body", ref.t, ref.y, rel_tol=1e-15).passed
assert eulervop.check(ref, ref.t, ref.y, rel_tol=1e-15).passed
print(len(ref.csv) > 0)
"""
    module_dir = os.path.dirname(os.path.abspath(eulervop.__file__))
    env = dict(os.environ, TMPDIR=str(tmp_path / "nowhere"), PYTHONPATH=module_dir)
    before = set(os.listdir(tmp_path))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "True"
    assert set(os.listdir(tmp_path)) == before


def test_cmake_install_puts_the_module_where_python_reads_it(binary, tmp_path):
    # Installed under a prefix, the module lands in the directory Debian's python3 reads under
    # /usr/local (its default scheme, which is on sys.path), and imports from there.
    import sysconfig
    platlib = sysconfig.get_path("platlib")
    relative = platlib[platlib.index("/lib/") + 1:]
    assert os.path.join("/usr/local", relative) == platlib and platlib in sys.path
    build = os.path.dirname(binary)
    out = subprocess.run(["cmake", "--install", build, "--prefix", str(tmp_path)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    where = tmp_path / relative
    assert list(where.glob("eulervop*.so")) and (where / "eulervop.pyi").exists()
    code = "import eulervop; print(eulervop.__file__); print(eulervop.Scene.load('paper-fig1').name)"
    run = subprocess.run([sys.executable, "-c", code], env=dict(os.environ, PYTHONPATH=str(where)),
                         capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == [str(next(where.glob("eulervop*.so"))), "paper-fig1"]
