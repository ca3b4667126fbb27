"""Type stubs of the eulervop module (docs/python.md)."""
from os import PathLike
from typing import Any, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

class NumericalFailure(ArithmeticError):
    """The reference integrator gave up: the message gives the time and the cause."""

class Scene:
    """A parsed scene (docs/scenes.md)."""
    @staticmethod
    def load(path: Union[str, PathLike[str]]) -> Scene: ...
    @staticmethod
    def from_toml(text: str) -> Scene: ...
    @property
    def name(self) -> str: ...
    @property
    def form(self) -> str: ...
    @property
    def text(self) -> str: ...
    @property
    def path(self) -> Optional[str]: ...

class Reference:
    """A reference solution, as `eulervop reference` writes it."""
    t: npt.NDArray[np.float64]
    y: npt.NDArray[np.float64]
    """The columns `check` reads by default: check(scene, ref.t, ref.y) judges the reference itself."""
    columns: list[str]
    normalized: Optional[npt.NDArray[np.float64]]
    """(n, 4): tau, Omega1..3, when the file has them; else None."""
    normalized_columns: list[str]
    all_columns: list[str]
    decimal: list[list[str]]
    meta: dict[str, Any]
    radius: Optional[npt.NDArray[np.float64]]
    radius_omega: Optional[npt.NDArray[np.float64]]
    radius_q: Optional[npt.NDArray[np.float64]]
    csv: str
    def __len__(self) -> int: ...

class CheckResult:
    """The verdict of `check`."""
    @property
    def passed(self) -> bool: ...
    @property
    def verdict(self) -> Optional[bool]: ...
    @property
    def max_error(self) -> float: ...
    exit_code: int
    def as_dict(self) -> dict[str, Any]: ...
    def __bool__(self) -> bool: ...

def reference(
    scene: Union[Scene, str, PathLike[str]],
    times: Optional[npt.ArrayLike] = None,
    precision: Optional[str] = None,
    verify: bool = False,
    certify: bool = False,
    samples: Optional[int] = None,
    t_end: Optional[float] = None,
    tau_end: Optional[float] = None,
) -> Reference: ...

def check(
    against: Union[Scene, Reference, str, PathLike[str]],
    t: Union[npt.ArrayLike, str, PathLike[str]],
    y: Optional[npt.ArrayLike] = None,
    columns: Optional[Sequence[str]] = None,
    tol: Optional[float] = None,
    rel_tol: Optional[float] = None,
    attitude_tol: Optional[float] = None,
    ignore_attitude: bool = False,
    precision: Optional[str] = None,
    scd_atol: Optional[float] = None,
    scd_rtol: Optional[float] = None,
) -> CheckResult: ...

def problems() -> dict[str, str]: ...
