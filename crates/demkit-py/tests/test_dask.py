"""examples/cohort_dask.py on a LocalCluster of 2 worker processes equals a serial loop."""

from __future__ import annotations

import csv
import os
import sys

import numpy as np
import pytest

import demkit

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "..", "examples")


def test_cohort_on_dask_equals_a_serial_loop(tmp_path, monkeypatch):
    distributed = pytest.importorskip("dask.distributed")
    examples = os.path.abspath(EXAMPLES)
    monkeypatch.syspath_prepend(examples)
    monkeypatch.setenv("PYTHONPATH", examples + os.pathsep + os.environ.get("PYTHONPATH", ""))
    import cohort_dask

    meshes = {
        "polygon.obj": demkit.generate("polygon", sides=6, rings=10),
        "peaks.ply": demkit.generate("peaks", n=20),
        "holes.obj": demkit.generate("disk_holes", holes=[(0.3, 0.0, 0.2)], resolution=30),
        "icosphere.obj": demkit.generate("icosphere", subdivisions=3),
        "uvsphere.obj": demkit.generate("uv_sphere", lat=16, lon=32),
        "annulus.obj": demkit.generate("annulus", radial=6, angular=48),
    }
    folder = tmp_path / "cohort"
    folder.mkdir()
    for name, (v, f) in meshes.items():
        demkit.write_mesh(folder / name, v, f)
    v, f = meshes["icosphere.obj"]
    np.savetxt(folder / "icosphere.population.txt", 1.0 + (v[f].mean(axis=1)[:, 2] > 0.2))

    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    with distributed.Client(cluster) as client:
        reports = cohort_dask.run(folder, client)
    cluster.close()
    assert len(reports) == 6
    outputs = {r["mesh"]: (folder / r["output"]).read_bytes() for r in reports}
    with open(folder / "cohort_metrics.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert sorted(r["mesh"] for r in rows) == sorted(meshes)
    assert "density_error_mean" in rows[0] and "flipped_triangles" in rows[0]

    for path in cohort_dask.meshes_in(folder):
        serial = cohort_dask.map_one(str(path))
        dask_report = next(r for r in reports if r["mesh"] == path.name)
        assert (folder / serial["output"]).read_bytes() == outputs[path.name], path.name
        assert serial["metrics"] == dask_report["metrics"]
        assert serial["history"] == dask_report["history"]
    assert {r["method"] for r in reports} == {"dem", "deq", "sdem"}
    assert next(r for r in reports if r["mesh"] == "icosphere.obj")["metrics"]["density_var_initial"] > 0.01
    del sys.modules["cohort_dask"]
