"""Type stubs of the native module demkit._demkit (use the functions of demkit instead)."""

from os import PathLike
from typing import Any, Callable, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

class InputError(ValueError):
    """Bad input: a malformed mesh, population, landmark, option or file."""

class NumericalError(RuntimeError):
    """A numerical step failed (not caused by the input), or an internal error."""

_Progress = Optional[Callable[[int, float, int], Any]]
_Mesh = Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]

def methods() -> list[str]: ...
def map(request: dict[str, Any], progress: _Progress = None) -> dict[str, Any]: ...
def remesh(request: dict[str, Any], n: int, progress: _Progress = None) -> _Mesh: ...
def read_mesh(path: Union[str, PathLike[str]]) -> _Mesh: ...
def write_mesh(
    path: Union[str, PathLike[str]],
    vertices: npt.NDArray[np.float64],
    faces_: npt.NDArray[np.int64],
) -> None: ...
def generate(kind: str, options: dict[str, Any]) -> _Mesh: ...
def cut_holes(
    vertices: npt.NDArray[np.float64],
    faces_: npt.NDArray[np.int64],
    holes: list[tuple[float, float, float, float]],
    planar: bool,
) -> _Mesh: ...
def metrics(
    vertices: npt.NDArray[np.float64],
    faces_: npt.NDArray[np.int64],
    mapped: npt.NDArray[np.float64],
    initial: npt.NDArray[np.float64],
    population: str,
    population_values: Optional[npt.NDArray[np.float64]],
    domain: str,
    landmark_indices: Optional[npt.NDArray[np.int64]] = None,
    landmark_targets: Optional[npt.NDArray[np.float64]] = None,
) -> str: ...
def cartogram(
    text: str,
    label: str,
    value: str,
    sphere: bool = False,
    project: bool = False,
    max_error: float = 0.01,
    grid: int = 1024,
    max_iter: Optional[int] = None,
) -> Tuple[str, list[str], bool]: ...
