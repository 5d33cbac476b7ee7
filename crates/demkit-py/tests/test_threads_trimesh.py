"""The GIL is released while mapping; trimesh meshes go in and come back out."""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import demkit


def test_threads_mapping_four_meshes_finish_faster_than_serially():
    meshes = [demkit.generate("icosphere", subdivisions=4) for _ in range(4)]
    population = "area*(1+2*(z>0.3))"

    def one(mesh):
        return demkit.map(*mesh, population=population)

    one(meshes[0])  # warm up
    t0 = time.perf_counter()
    serial = [one(m) for m in meshes]
    t_serial = time.perf_counter() - t0
    t0 = time.perf_counter()
    with ThreadPoolExecutor(4) as pool:
        threaded = list(pool.map(one, meshes))
    t_threads = time.perf_counter() - t0
    print(f"4 maps: serial {t_serial:.2f} s, 4 threads {t_threads:.2f} s")
    for a, b in zip(serial, threaded):
        assert np.array_equal(a.vertices, b.vertices)
    assert t_threads < 0.9 * t_serial


def test_trimesh_round_trip(tmp_path, sphere):
    trimesh = pytest.importorskip("trimesh")
    v, f = sphere
    mesh = trimesh.Trimesh(vertices=v, faces=f, process=False)
    m = demkit.map(mesh, population="area*(1+2*(z>0.3))")
    assert np.array_equal(m.vertices, demkit.map(v, f, population="area*(1+2*(z>0.3))").vertices)
    mapped = trimesh.Trimesh(vertices=m.vertices, faces=m.faces, process=False)
    assert mapped.is_watertight and mapped.is_winding_consistent
    # The mapped mesh is on the unit sphere with outward normals, as the input was.
    assert np.allclose(np.linalg.norm(mapped.vertices, axis=1), 1.0)
    assert mapped.volume > 0
    # Files written by either side are read by the other.
    path = tmp_path / "mapped.obj"
    demkit.write_mesh(path, mapped)
    back = trimesh.load(path, process=False, force="mesh")
    assert np.array_equal(np.asarray(back.faces), m.faces)
    assert np.allclose(np.asarray(back.vertices), m.vertices, rtol=0, atol=1e-12)
    path2 = tmp_path / "by_trimesh.ply"
    mapped.export(path2)
    v2, f2 = demkit.read_mesh(path2)
    assert np.array_equal(f2, m.faces)
    assert np.allclose(v2, m.vertices, rtol=0, atol=1e-6)  # trimesh writes PLY in float32
