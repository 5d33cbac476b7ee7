"""Every input form of demkit.map is accepted and gives the same map."""

from __future__ import annotations

import numpy as np
import pytest

import demkit


def same(a, b):
    return np.array_equal(np.asarray(a).view(np.uint64), np.asarray(b).view(np.uint64))


def test_vertex_dtypes_and_memory_orders(disk):
    v, f = disk
    ref = demkit.map(v, f)
    assert ref.vertices.shape == (len(v), 3) and ref.vertices.dtype == np.float64
    assert same(demkit.map(np.asfortranarray(v), f).vertices, ref.vertices)
    assert same(demkit.map(v[:, :2].copy(), f).vertices, ref.vertices)  # (n, 2)
    wide = np.zeros((len(v), 6))
    wide[:, ::2] = v
    assert same(demkit.map(wide[:, ::2], f).vertices, ref.vertices)  # strided view
    v32 = v.astype(np.float32)
    assert same(demkit.map(v32, f).vertices, demkit.map(v32.astype(np.float64), f).vertices)
    assert same(demkit.map(v.tolist(), f.tolist()).vertices, ref.vertices)


@pytest.mark.parametrize("dtype", [np.int8, np.int16, np.int32, np.int64, np.uint16, np.uint32, np.uint64, np.intp])
def test_face_dtypes(dtype):
    v, f = demkit.generate("polygon", sides=6, rings=4)  # 61 vertices: fits int8
    ref = demkit.map(v, f)
    assert same(demkit.map(v, np.asfortranarray(f.astype(dtype))).vertices, ref.vertices)


def test_populations(disk):
    v, f = disk
    area = demkit.map(v, f, population="area")
    assert demkit.map(v, f, population="uniform").converged
    expr = demkit.map(v, f, population="area*(1+3*(x>0))")
    assert expr.report["metrics"]["density_var_initial"] > area.report["metrics"]["density_var_initial"]
    values = expr.population * 7.0
    from_array = demkit.map(v, f, population=values)
    assert np.allclose(from_array.vertices, expr.vertices, atol=1e-9)
    assert demkit.map(v, f, population=list(values)).converged
    assert demkit.map(v, f, population=values.astype(np.float32)).converged


def test_landmarks_on_the_sphere_in_both_forms(sphere):
    v, f = sphere
    idx = np.array([0, 5, 17])
    targets = v[[1, 6, 18]] / np.linalg.norm(v[[1, 6, 18]], axis=1, keepdims=True)
    a = demkit.map(v, f, landmarks=(idx, targets), max_iter=5)
    b = demkit.map(v, f, landmarks=np.column_stack([idx, targets]), max_iter=5)
    assert a.method == "lsdem" and same(a.vertices, b.vertices)
    assert a.report["metrics"]["landmark_error"] is not None
    assert a.domain.kind == "sphere"


def test_landmarks_in_the_plane_in_both_forms(holes):
    v, f = holes
    # Interior vertices, away from the holes.
    idx = np.array([np.argmin(np.linalg.norm(v[:, :2] - p, axis=1)) for p in ([0.0, 0.6], [0.0, -0.6])])
    targets2 = v[idx, :2] * 0.95
    a = demkit.map(v, f, landmarks=(idx, targets2), max_iter=5)
    b = demkit.map(v, f, landmarks=np.column_stack([idx, targets2, np.zeros(2)]), max_iter=5)
    c = demkit.map(v, f, landmarks=np.column_stack([idx, targets2]), max_iter=5)  # (k, 3): index x y
    assert a.method == "ldeq" and same(a.vertices, b.vertices) and same(a.vertices, c.vertices)
    assert a.domain.kind == "circle_domain" and len(a.domain.circles) == 2


def test_torus_and_domains(torus, holes, disk, sphere):
    t = demkit.map(*torus, torus=(3, 1))
    assert t.method == "tdem" and t.domain.kind == "torus" and t.domain.torus == (3.0, 1.0)
    assert t.vertices.shape == (len(torus[0]), 3)
    assert demkit.map(*holes).domain.kind == "circle_domain"
    assert demkit.map(*disk).domain.kind == "plane"
    s = demkit.map(*sphere)
    assert s.domain.kind == "sphere" and np.allclose(np.linalg.norm(s.vertices, axis=1), 1.0)
    assert s.initial.shape == s.vertices.shape
    assert s.stop_reason in ("tolerance", "stationary", "max_iter") and s.flipped_triangles == 0


def test_options_and_methods(disk):
    v, f = disk
    assert demkit.map(v, f, method="dem-shape", shape="square").method == "dem-shape"
    m = demkit.map(v, f, max_iter=2, epsilon=1e-12, dt=0.05)
    assert m.report["iterations"] <= 2
    assert "auto" in demkit.methods()


def test_objects_with_vertices_and_faces(disk):
    class Mesh:
        def __init__(self, vertices, faces):
            self.vertices, self.faces = vertices, faces

    v, f = disk
    assert same(demkit.map(Mesh(v, f)).vertices, demkit.map(v, f).vertices)


def test_progress_callable_and_bar(disk):
    v, f = disk
    seen = []
    m = demkit.map(v, f, population="area*(1+(x>0))", progress=lambda i, e: seen.append((i, e)))
    assert [i for i, _ in seen] == list(range(1, m.report["iterations"] + 1))
    assert [e for _, e in seen] == [h["error"] for h in m.report["history"]]
    assert demkit.map(v, f, progress=True).converged


def test_an_exception_in_the_callback_is_raised(disk):
    def fail(i, e):
        raise KeyError("stop")

    with pytest.raises(KeyError):
        demkit.map(*disk, population="area*(1+(x>0))", progress=fail)


def test_files_generate_metrics_remesh(tmp_path, disk, sphere):
    v, f = disk
    demkit.write_mesh(tmp_path / "d.ply", v, f)
    v2, f2 = demkit.read_mesh(str(tmp_path / "d.ply"))
    assert same(v2, v) and np.array_equal(f2, f)
    m = demkit.map(v, f)
    metrics = demkit.metrics(v, f, m.vertices, initial=m.initial)
    assert metrics == m.report["metrics"]
    nv, nf = demkit.remesh(*sphere, n_vertices=300)
    assert nf.shape[1] == 3 and 200 < len(nv) < 400
    for kind in ("grid", "polygon", "peaks", "gaussian", "annulus", "disk_holes", "rect_holes", "icosphere", "uv_sphere", "torus"):
        gv, gf = demkit.generate(kind)
        assert gv.shape[1] == 3 and gf.dtype == np.int64, kind


def test_cartogram_from_dict_text_and_path(tmp_path):
    def square(x, y):
        return [[[x, y], [x + 1, y], [x + 1, y + 1], [x, y + 1], [x, y]]]

    fc = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": n, "pop": p}, "geometry": {"type": "Polygon", "coordinates": square(x, y)}}
        for n, p, x, y in [("a", 1.0, 0, 0), ("b", 3.0, 1, 0), ("c", 2.0, 0, 1), ("d", 2.0, 1, 1)]
    ]}
    out = demkit.cartogram(fc, value="pop", grid=64)
    assert out["type"] == "FeatureCollection" and len(out["features"]) == 4
    assert out["features"][1]["properties"]["name"] == "b"
    import json
    path = tmp_path / "r.geojson"
    path.write_text(json.dumps(fc))
    assert demkit.cartogram(path, value="pop", grid=64) == out
    assert demkit.cartogram(json.dumps(fc), value="pop", grid=64) == out
