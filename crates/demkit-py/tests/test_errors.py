"""Bad input raises demkit.InputError with the command line's message, never a panic."""

from __future__ import annotations

import numpy as np
import pytest

import demkit


def raises(match, *args, **kwargs):
    with pytest.raises(demkit.InputError, match=match) as e:
        demkit.map(*args, **kwargs)
    assert isinstance(e.value, ValueError)
    assert "\n" not in str(e.value)
    return str(e.value)


def test_wrong_shapes(disk):
    v, f = disk
    raises(r"vertices must be an \(n, 3\) or \(n, 2\) array, got shape \(\d+, 4\)", np.zeros((len(v), 4)), f)
    raises(r"vertices must be an \(n, 3\) or \(n, 2\) array", v.ravel(), f)
    raises(r"faces must be an \(m, 3\) integer array, got shape \(\d+, 4\)", v, np.zeros((len(f), 4), dtype=int))
    raises(r"faces must be an \(m, 3\) integer array", v, f.ravel())
    raises(r"landmarks must be", v, f, landmarks=np.zeros((2, 5)))
    raises(r"torus must be \(R, r\)", v, f, torus=3)
    raises(r"torus must be \(R, r\)", v, f, torus=(3, 1, 1))


def test_wrong_dtypes(disk):
    v, f = disk
    raises(r"faces must be an integer array, got dtype float64", v, f.astype(float))
    raises(r"vertices must be a float array \(float32 or float64\), got dtype int64", v.astype(np.int64), f)
    raises(r"vertices must be a float array", v.astype(str), f)
    raises(r"vertices must be a float array", v.astype(complex), f)
    raises(r"invalid population: must be", v, f, population=np.array(["a"] * len(f)))


def test_non_finite_coordinates(disk):
    v, f = disk
    for bad in (np.nan, np.inf):
        w = v.copy()
        w[7, 1] = bad
        raises(r"^invalid mesh: vertex 7 has a non-finite coordinate", w, f)


def test_faces_out_of_range(disk):
    v, f = disk
    g = f.copy()
    g[4, 2] = len(v) + 3
    raises(rf"^invalid mesh: face 4 uses vertex {len(v) + 3}, which is out of range \(the mesh has {len(v)} vertices\)", v, g)
    g[4, 2] = -1
    raises(r"^invalid mesh: face 4 uses vertex -1, which is out of range", v, g)
    g[4, 2] = 2**40
    raises(r"^invalid mesh: face 4 uses vertex 1099511627776, which is out of range", v, g)


def test_wrong_population(disk):
    v, f = disk
    raises(rf"^invalid population: population has 3 values but the mesh has {len(f)} faces$", v, f, population=np.ones(3))
    raises(r"^invalid population:", v, f, population=-np.ones(len(f)))
    raises(r"^invalid population:", v, f, population="x +* 2")
    raises(r"invalid population: must be an \(m,\) array", v, f, population=np.ones((len(f), 2)))


def test_options(disk, torus, sphere):
    raises(r"^invalid argument: epsilon must be positive", *disk, epsilon=-1.0)
    raises(r"^unknown method 'nope' \(one of auto, dem", *disk, method="nope")
    raises(r"method 'tdem' \(for genus-one closed surfaces\) needs the target torus", *torus)
    raises(r"^torus: ", *torus, torus=(1.0, 2.0))
    raises(r"method 'lsdem' needs landmarks", *sphere, method="lsdem")
    raises(r"^wrong topology for ", *sphere, method="dem")
    raises(r"invalid landmarks: landmark 0 names vertex 999999", *sphere, landmarks=([999999], [[0.0, 0.0, 1.0]]))


def test_other_functions(tmp_path, disk):
    with pytest.raises(demkit.InputError, match="no-such.obj"):
        demkit.read_mesh(tmp_path / "no-such.obj")
    with pytest.raises(demkit.InputError, match="unknown kind 'cube'"):
        demkit.generate("cube")
    with pytest.raises(demkit.InputError, match="takes sides, rings; got 'n'"):
        demkit.generate("polygon", n=3)
    with pytest.raises(demkit.InputError, match="rings"):
        demkit.generate("polygon", rings=0)
    with pytest.raises(demkit.InputError, match="out of range"):
        demkit.write_mesh(tmp_path / "x.obj", disk[0], disk[1] + 10**6)
    with pytest.raises(demkit.InputError):
        demkit.cartogram({"type": "FeatureCollection", "features": []}, value="pop")
    assert issubclass(demkit.NumericalError, RuntimeError)
