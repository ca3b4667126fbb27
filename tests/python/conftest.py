"""Shared fixtures of the Python module's tests: the module from the build tree and the program
beside it (ctest sets PYTHONPATH and EULERVOP_BINARY)."""
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def binary():
    path = os.environ.get("EULERVOP_BINARY", str(ROOT / "build" / "eulervop"))
    assert os.access(path, os.X_OK), f"no eulervop program at {path}"
    return path


@pytest.fixture(scope="session")
def root():
    return ROOT
