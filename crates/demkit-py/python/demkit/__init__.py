"""demkit: density-equalizing maps of triangle meshes.

numpy in, numpy out. ``demkit.map(v, f)`` maps a surface onto its standard domain (the plane,
a circle domain, the unit sphere, an ellipsoid or a torus) so that a population per face becomes uniform per
unit area; population "area" gives an area-preserving parameterization. The computation runs
in Rust with the GIL released, so threads map several meshes at once.
"""

from __future__ import annotations

import json
import os
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _demkit
from ._demkit import InputError, NumericalError

__all__ = [
    "Domain",
    "InputError",
    "Map",
    "NumericalError",
    "cartogram",
    "cut_holes",
    "generate",
    "map",
    "methods",
    "metrics",
    "read_mesh",
    "remesh",
    "write_mesh",
]

__version__ = "0.1.0"


@dataclass(frozen=True)
class Domain:
    """Where a map lies.

    kind     "plane", "circle_domain", "sphere", "ellipsoid" or "torus"
    circles  circle domain: ((cx, cy), r) of every hole, in boundary-loop order (outer circle left out)
    torus    torus: (R, r), the radii in input units
    radii    ellipsoid: (a, b, c), its semi-axes along x, y, z (edeq: the ones it chose)
    """

    kind: str
    circles: Tuple[Tuple[Tuple[float, float], float], ...] = ()
    torus: Optional[Tuple[float, float]] = None
    radii: Optional[Tuple[float, float, float]] = None


@dataclass(frozen=True, eq=False)
class Map:
    """A computed density-equalizing map.

    vertices           (n, 3) float64 mapped position of every vertex (z = 0 for planar maps)
    initial            (n, 3) float64 initial map (after initialization, before equalization)
    faces              (m, 3) int64 faces of the mapped surface (the input's, or its refinement)
    population         (m,) float64 population of each face, scaled to a unit mean
    report             dict with exactly the JSON report's names (``demkit map --report``)
    method             the method that ran ("dem", "sdem", "deq", "tdem", ...)
    domain             where the map lies (Domain)
    warnings           what validation noticed without refusing the mesh
    """

    vertices: np.ndarray
    initial: np.ndarray
    faces: np.ndarray
    population: np.ndarray
    report: dict
    method: str
    domain: Domain
    warnings: Tuple[str, ...] = field(default=())

    @property
    def converged(self) -> bool:
        """True unless the iteration limit ran out."""
        return bool(self.report["converged"])

    @property
    def stop_reason(self) -> str:
        """"tolerance", "stationary" or "max_iter"."""
        return str(self.report["stop_reason"])

    @property
    def flipped_triangles(self) -> int:
        """Number of faces the map flipped (0 for a bijective map)."""
        return int(self.report["metrics"]["flipped_triangles"])

    @property
    def metrics(self) -> dict:
        """The report's metrics."""
        return self.report["metrics"]

    def __repr__(self) -> str:
        m = self.report["metrics"]
        return (
            f"Map(method={self.method!r}, vertices={len(self.vertices)}, domain={self.domain.kind!r}, "
            f"converged={self.converged}, iterations={self.report['iterations']}, "
            f"density_error_mean={m['density_error_mean']:.4g}, flipped_triangles={self.flipped_triangles})"
        )


def methods() -> list:
    """Names of every method.

    Returns:
        list of str, "auto" first
    """
    return list(_demkit.methods())


# ----------------------------------------------------------------------------- input forms


def _mesh_args(vertices: Any, faces: Any) -> Tuple[Any, Any]:
    """(vertices, faces) from two arrays or from one object with .vertices and .faces."""
    if faces is None:
        if hasattr(vertices, "vertices") and hasattr(vertices, "faces"):
            return vertices.vertices, vertices.faces
        raise InputError("faces missing: give (vertices, faces) or an object with .vertices and .faces")
    return vertices, faces


def _as_vertices(vertices: Any, name: str = "vertices") -> np.ndarray:
    """An (n, 3) C-contiguous float64 array from an (n, 3) or (n, 2) float array."""
    a = np.asarray(vertices)
    if a.dtype.kind != "f" or a.dtype.itemsize not in (4, 8):
        raise InputError(f"{name} must be a float array (float32 or float64), got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] not in (2, 3):
        raise InputError(f"{name} must be an (n, 3) or (n, 2) array, got shape {a.shape}")
    if a.shape[1] == 2:
        a = np.concatenate([a.astype(np.float64), np.zeros((a.shape[0], 1))], axis=1)
    return np.ascontiguousarray(a, dtype=np.float64)


def _as_faces(faces: Any) -> np.ndarray:
    """An (m, 3) C-contiguous int64 array from an (m, 3) array of any integer dtype."""
    a = np.asarray(faces)
    if a.dtype.kind not in "iu":
        raise InputError(f"faces must be an integer array, got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] != 3:
        raise InputError(f"faces must be an (m, 3) integer array, got shape {a.shape}")
    if a.dtype == np.uint64 and a.size and a.max() > np.iinfo(np.int64).max:
        bad = int(np.argmax(a.max(axis=1)))
        raise InputError(f"invalid mesh: face {bad} uses vertex {a[bad].max()}, which is out of range")
    return np.ascontiguousarray(a, dtype=np.int64)


def _landmarks(landmarks: Any) -> Tuple[Optional[np.ndarray], Optional[np.ndarray]]:
    """(indices (k,) int64, targets (k, 3) float64) from (indices, targets) or a (k, 3|4) array."""
    if landmarks is None:
        return None, None
    if isinstance(landmarks, (tuple, list)) and len(landmarks) == 2 and np.ndim(landmarks[1]) == 2:
        idx, targets = np.asarray(landmarks[0]), np.asarray(landmarks[1], dtype=np.float64)
    else:
        a = np.asarray(landmarks, dtype=np.float64)
        if a.ndim != 2 or a.shape[1] not in (3, 4):
            raise InputError(
                f"landmarks must be (indices, targets) or a (k, 3|4) array of rows 'index x y [z]', got shape {a.shape}"
            )
        if not np.all(a[:, 0] == np.round(a[:, 0])):
            raise InputError("invalid landmarks: the first column holds vertex indices, which must be integers")
        idx, targets = a[:, 0], a[:, 1:]
    idx = np.asarray(idx)
    if idx.ndim != 1 or (idx.dtype.kind == "f" and not np.all(idx == np.round(idx))) or idx.dtype.kind not in "iuf":
        raise InputError(f"invalid landmarks: indices must be a (k,) integer array, got shape {idx.shape}")
    if targets.ndim != 2 or targets.shape[1] not in (2, 3) or len(targets) != len(idx):
        raise InputError(
            f"invalid landmarks: {len(idx)} indices need ({len(idx)}, 2) or ({len(idx)}, 3) targets, got shape {targets.shape}"
        )
    if targets.shape[1] == 2:
        targets = np.concatenate([targets, np.zeros((len(targets), 1))], axis=1)
    return np.ascontiguousarray(idx, dtype=np.int64), np.ascontiguousarray(targets, dtype=np.float64)


def _population(population: Any) -> Tuple[str, Optional[np.ndarray]]:
    """("area" | "uniform" | expression, None) or ("", values (m,) float64)."""
    if isinstance(population, str):
        return population, None
    a = np.asarray(population)
    if a.dtype.kind not in "fiu":
        raise InputError(f"invalid population: must be 'area', 'uniform', an expression or an (m,) array, got dtype {a.dtype}")
    if a.ndim != 1:
        raise InputError(f"invalid population: must be an (m,) array with one value per face, got shape {a.shape}")
    return "", np.ascontiguousarray(a, dtype=np.float64)


def _progress(progress: Any, label: str) -> Tuple[Optional[Callable], Callable[[], None]]:
    """The native callback (iteration, error, max_iter) and a function closing any bar."""
    if progress is None or progress is False:
        return None, lambda: None
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return None, lambda: None
        bar = tqdm(desc=label, total=1, leave=False)

        def update(iteration: int, error: float, max_iter: int) -> None:
            bar.total = max_iter
            bar.n = iteration
            bar.set_postfix_str(f"error {error:.3e}", refresh=False)
            bar.refresh()

        return update, bar.close
    if callable(progress):
        return (lambda iteration, error, _max_iter: progress(iteration, error)), lambda: None
    raise InputError("progress must be True, False or a callable taking (iteration, error)")


def _numbers(value: Any, n: int, name: str, form: str) -> Optional[tuple]:
    """A tuple of n floats from a sequence (None stays None); InputError naming the option."""
    if value is None:
        return None
    try:
        if len(value) != n:
            raise ValueError
        return tuple(float(x) for x in value)
    except (TypeError, ValueError, IndexError):
        raise InputError(f"{name} must be {form}, got {value!r}") from None


def _request(vertices, faces, population, method, landmarks, torus, shape, alpha, beta, gamma, dt, epsilon, max_iter, fixed_holes, ellipsoid=None) -> dict:
    """The arguments of map() checked and converted into the native module's request dict."""
    v, f = _mesh_args(vertices, faces)
    pop, values = _population(population)
    idx, targets = _landmarks(landmarks)
    torus = _numbers(torus, 2, "torus", "(R, r) with numbers R > r > 0")
    ellipsoid = _numbers(ellipsoid, 3, "ellipsoid", "(a, b, c) with numbers a, b, c > 0")
    if max_iter is not None and (not isinstance(max_iter, (int, np.integer)) or max_iter < 0):
        raise InputError(f"max_iter must be a non-negative integer, got {max_iter!r}")
    floats = dict(alpha=alpha, beta=beta, gamma=gamma, dt=dt, epsilon=epsilon)
    for k, x in floats.items():
        if x is not None:
            try:
                floats[k] = float(x)
            except (TypeError, ValueError):
                raise InputError(f"{k} must be a number, got {x!r}") from None
    return dict(
        vertices=_as_vertices(v),
        faces=_as_faces(f),
        population=pop,
        population_values=values,
        method=str(method),
        landmark_indices=idx,
        landmark_targets=targets,
        torus=torus,
        ellipsoid=ellipsoid,
        shape=shape,
        max_iter=None if max_iter is None else int(max_iter),
        fixed_holes=bool(fixed_holes),
        **floats,
    )


# ----------------------------------------------------------------------------- functions


def map(
    vertices: Any,
    faces: Any = None,
    population: Union[str, Sequence[float], np.ndarray] = "area",
    method: str = "auto",
    landmarks: Any = None,
    torus: Optional[Tuple[float, float]] = None,
    shape: Optional[str] = None,
    alpha: Optional[float] = None,
    beta: Optional[float] = None,
    gamma: Optional[float] = None,
    dt: Optional[float] = None,
    epsilon: Optional[float] = None,
    max_iter: Optional[int] = None,
    progress: Union[bool, Callable[[int, float], Any]] = False,
    fixed_holes: bool = False,
    ellipsoid: Optional[Tuple[float, float, float]] = None,
) -> Map:
    """Density-equalizing map of a triangle mesh (``demkit map``).

    Args:
        vertices    (n, 3) or (n, 2) float32/float64 positions, any memory order; or an object with .vertices and .faces
        faces       (m, 3) integer vertex indices, counter-clockwise (any integer dtype)
        population  "area", "uniform", an expression of the face centroid x, y, z and its area, or (m,) values
        method      "auto" (by topology), "dem", "dem-shape", "sdem", "lsdem", "edem", "edeq", "deq", "ldeq", "tdem", "spherical-conformal", "circle-conformal"
        landmarks   (indices (k,), targets (k, 2|3)) or a (k, 3|4) array of rows "index x y [z]"
        torus       (R, r) target torus of tdem, R > r > 0
        shape       target of dem-shape: "disk", "square", "rectangle:W:H", "ellipse:A:B"
        alpha       energy weight of lsdem / deq (default: the paper's)
        beta        energy weight of lsdem's harmonic term
        gamma       energy weight of lsdem's landmark term
        dt          fixed time step instead of the method's rule
        epsilon     stopping tolerance
        max_iter    iteration limit
        progress    True for a tqdm bar, or a callable receiving (iteration, error)
        fixed_holes deq/ldeq: keep every hole on its initial circle
        ellipsoid   (a, b, c) target ellipsoid of edem, initial guess of edeq (default: from the extents); with method "auto" a genus-0 closed surface is mapped by edem
        alpha       (as above) edeq: weight of the distortion Σ|μ|² against the density gradient (default 5)

    Returns:
        Map with .vertices (n, 3) float64, .initial, .report, .method, .converged, .stop_reason, .domain, .flipped_triangles

    Raises:
        InputError      bad input (the message names the face, vertex or option)
        NumericalError  a numerical step failed
    """
    request = _request(vertices, faces, population, method, landmarks, torus, shape, alpha, beta, gamma, dt, epsilon, max_iter, fixed_holes, ellipsoid)
    callback, close = _progress(progress, str(method))
    try:
        out = _demkit.map(request, callback)
    finally:
        close()
    for w in out["warnings"]:
        warnings.warn(w, stacklevel=2)
    d = out["domain"]
    domain = Domain(
        kind=d["kind"],
        circles=tuple((tuple(c), r) for c, r in d.get("circles", ())),
        torus=tuple(d["torus"]) if "torus" in d else None,
        radii=tuple(d["radii"]) if "radii" in d else None,
    )
    return Map(
        vertices=out["vertices"],
        initial=out["initial"],
        faces=out["faces"],
        population=np.asarray(out["population"], dtype=np.float64),
        report=json.loads(out["report"]),
        method=out["method"],
        domain=domain,
        warnings=tuple(out["warnings"]),
    )


def remesh(
    vertices: Any,
    faces: Any = None,
    n_vertices: int = 5000,
    population: Union[str, Sequence[float], np.ndarray] = "area",
    method: str = "auto",
    landmarks: Any = None,
    torus: Optional[Tuple[float, float]] = None,
    alpha: Optional[float] = None,
    epsilon: Optional[float] = None,
    max_iter: Optional[int] = None,
    progress: Union[bool, Callable[[int, float], Any]] = False,
    ellipsoid: Optional[Tuple[float, float, float]] = None,
) -> Tuple[np.ndarray, np.ndarray]:
    """New triangulation laid out through the density-equalizing map (``demkit remesh``).

    Args:
        vertices    (n, 3) or (n, 2) float positions; or an object with .vertices and .faces
        faces       (m, 3) integer vertex indices
        n_vertices  about how many vertices the new mesh has
        population  sets the vertex density: "area" (uniform), "uniform", an expression, or (m,) values
        method      the map's method ("auto" by topology)
        landmarks   as in map()
        torus       (R, r) for genus-one surfaces
        ellipsoid   (a, b, c) for a map onto an ellipsoid (edem)
        alpha       energy weight (deq default: the remeshing value)
        epsilon     stopping tolerance of the map
        max_iter    iteration limit of the map
        progress    True for a tqdm bar, or a callable receiving (iteration, error)

    Returns:
        V  (k, 3) float64 new vertex positions, on the input surface
        F  (l, 3) int64 new faces
    """
    if not isinstance(n_vertices, (int, np.integer)) or n_vertices < 0:
        raise InputError(f"n_vertices must be a non-negative integer, got {n_vertices!r}")
    request = _request(vertices, faces, population, method, landmarks, torus, None, alpha, None, None, None, epsilon, max_iter, False, ellipsoid)
    callback, close = _progress(progress, "remesh")
    try:
        return _demkit.remesh(request, int(n_vertices), callback)
    finally:
        close()


def read_mesh(path: Union[str, os.PathLike]) -> Tuple[np.ndarray, np.ndarray]:
    """Read a mesh file.

    Args:
        path  .obj, .ply (ascii or binary), .off or .stl file

    Returns:
        V  (n, 3) float64 vertex positions
        F  (m, 3) int64 faces
    """
    return _demkit.read_mesh(os.fspath(path))


def write_mesh(path: Union[str, os.PathLike], vertices: Any, faces: Any = None) -> None:
    """Write a mesh file (atomically).

    Args:
        path      .obj or .ply file
        vertices  (n, 3) or (n, 2) float positions; or an object with .vertices and .faces
        faces     (m, 3) integer vertex indices
    """
    v, f = _mesh_args(vertices, faces)
    _demkit.write_mesh(os.fspath(path), _as_vertices(v), _as_faces(f))


def generate(kind: str, **options: Any) -> Tuple[np.ndarray, np.ndarray]:
    """Synthetic mesh (``demkit generate KIND``).

    Args:
        kind     "grid" (nx, ny, width, height), "polygon" (sides, rings), "peaks" (n), "gaussian" (n),
                 "annulus" (inner, outer, radial, angular), "disk_holes" (holes=[(cx, cy, r)], resolution),
                 "rect_holes" (width, height, holes, resolution), "icosphere" (subdivisions),
                 "uv_sphere" (lat, lon), "torus" (R, r, major, minor)
        options  the kind's parameters; defaults as on the command line

    Returns:
        V  (n, 3) float64 vertex positions
        F  (m, 3) int64 faces
    """
    if "holes" in options:
        options["holes"] = [tuple(float(x) for x in h) for h in options["holes"]]
    return _demkit.generate(kind, options)


def cut_holes(
    vertices: Any,
    faces: Any = None,
    holes: Sequence[Sequence[float]] = (),
    planar: bool = False,
) -> Tuple[np.ndarray, np.ndarray]:
    """Cut holes into a surface around points (``demkit cut``).

    Every face whose centroid lies within r of (x, y, z) is removed, then the faces at a
    vertex where two loops touch, and every piece but the largest.

    Args:
        vertices  (n, 3) or (n, 2) float positions; or an object with .vertices and .faces
        faces     (m, 3) integer vertex indices
        holes     (x, y, z, r) per hole, r > 0
        planar    measure the distance in the plane z = 0 (a cylinder through the surface)

    Returns:
        V  (k, 3) float64 vertex positions, the kept vertices in their input order
        F  (l, 3) int64 faces
    """
    v, f = _mesh_args(vertices, faces)
    try:
        rows = [tuple(float(x) for x in h) for h in holes]
    except (TypeError, ValueError):
        raise InputError("cut_holes: every hole is (x, y, z, r), four numbers") from None
    if not rows or any(len(h) != 4 for h in rows):
        raise InputError("cut_holes: give at least one hole, each (x, y, z, r)")
    return _demkit.cut_holes(_as_vertices(v), _as_faces(f), rows, bool(planar))


def metrics(
    vertices: Any,
    faces: Any,
    mapped: Any,
    population: Union[str, Sequence[float], np.ndarray] = "area",
    initial: Any = None,
    domain: str = "plane",
    landmarks: Any = None,
) -> dict:
    """The report's metrics of a map computed elsewhere.

    Args:
        vertices    (n, 3) or (n, 2) float input positions
        faces       (m, 3) integer vertex indices
        mapped      (n, 3) or (n, 2) float mapped positions
        population  "area", "uniform", an expression, or (m,) values
        initial     (n, 3) or (n, 2) initial map for the *_initial metrics (default: mapped)
        domain      "plane" or "sphere"
        landmarks   as in map(), for landmark_error

    Returns:
        dict with the report's "metrics" names
    """
    v, f = _as_vertices(vertices), _as_faces(faces)
    m = _as_vertices(mapped, "mapped")
    i = m if initial is None else _as_vertices(initial, "initial")
    pop, values = _population(population)
    idx, targets = _landmarks(landmarks)
    return json.loads(_demkit.metrics(v, f, m, i, pop, values, str(domain), idx, targets))


def cartogram(
    geojson: Union[dict, str, os.PathLike],
    value: str,
    sphere: bool = False,
    project: bool = False,
    max_error: float = 0.01,
    grid: int = 1024,
    max_iter: Optional[int] = None,
) -> dict:
    """Cartogram of GeoJSON regions, each region's area following a value (``demkit cartogram``).

    Args:
        geojson    FeatureCollection of polygons: a dict, GeoJSON text, or a path to a file
        value      numeric feature property setting each region's area
        sphere     coordinates are longitude/latitude degrees: compute on the globe
        project    coordinates are longitude/latitude degrees: compute in the Equal Earth projection (km)
        max_error  accuracy asked for: relative error of each region's share
        grid       the flow's grid: cells along the longer side, a power of two from 16 to 8192
        max_iter   integration steps per round (default: the method's own)

    Returns:
        dict, a GeoJSON FeatureCollection with the same features and properties (geopandas.GeoDataFrame.from_features)
    """
    if isinstance(geojson, dict):
        text, label = json.dumps(geojson), "<geojson>"
    elif isinstance(geojson, str) and geojson.lstrip().startswith("{"):
        text, label = geojson, "<geojson>"
    elif isinstance(geojson, (str, os.PathLike)):
        path = os.fspath(geojson)
        try:
            with open(path, encoding="utf-8") as fh:
                text = fh.read()
        except OSError as e:
            raise InputError(f"{path}: {e.strerror}") from None
        label = path
    else:
        raise InputError(f"geojson must be a dict, GeoJSON text or a path, got {type(geojson).__name__}")
    out, notes, converged = _demkit.cartogram(text, label, value, sphere, project, float(max_error), int(grid), max_iter)
    for n in notes:
        warnings.warn(n, stacklevel=2)
    return json.loads(out)
