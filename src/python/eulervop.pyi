"""Type stubs of the eulervop module (docs/python.md)."""
from os import PathLike
from typing import Any, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

class NumericalFailure(ArithmeticError):
    """The reference integrator gave up: the message gives the time and the cause."""

class Scene:
    """A parsed, validated scene (docs/scenes.md)."""
    @staticmethod
    def load(path: Union[str, PathLike[str]]) -> Scene:
        """A scene file, or the shipped scene of that name (problems())."""
    @staticmethod
    def from_toml(text: str) -> Scene: ...
    @staticmethod
    def from_dict(scene: dict[str, Any]) -> Scene:
        """The TOML's tables as a dict (as as_dict() gives them)."""
    def as_dict(self) -> dict[str, Any]: ...
    @property
    def name(self) -> str: ...
    @property
    def form(self) -> str: ...
    @property
    def text(self) -> str: ...
    @property
    def path(self) -> Optional[str]: ...

class Reference:
    """A reference solution held in memory: its columns as float64 arrays."""
    t: npt.NDArray[np.float64]
    """The sample times, each exactly the float64 the reference was computed at."""
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
    """With certify=True: per row, a proven bound on the 2-norm of the printed state's distance
    from the exact solution at that row's time, in the state's units, rounded up to float64."""
    radius_omega: Optional[npt.NDArray[np.float64]]
    """The same for the printed omega1..3 of a physical scene, in rad/s."""
    radius_q: Optional[npt.NDArray[np.float64]]
    """A bound on |q - q*|_2 of the printed quaternion."""
    csv: str
    scene: Scene
    def __len__(self) -> int: ...

class CheckResult:
    """The verdict and the figures of `check`."""
    @property
    def passed(self) -> Optional[bool]:
        """None when no bar was given: then there is no verdict."""
    @property
    def verdict(self) -> Optional[bool]: ...
    @property
    def max_error(self) -> float: ...
    exit_code: int
    def as_dict(self) -> dict[str, Any]: ...
    def __bool__(self) -> bool:
        """The verdict; ValueError when no bar was given."""

def reference(
    scene: Union[Scene, str, PathLike[str]],  # a str may be a shipped scene's name
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

def scene_template(form: str = "physical") -> str: ...
