"""demkit.map gives the command line's vertices, bit for bit."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

import demkit

CASES = {
    # name: (fixture, population, extra CLI flags, extra keyword arguments)
    "disk": ("disk", "area*(1+3*(x>0))", [], {}),
    "sphere": ("sphere", "area*(1+2*(z>0.3))", [], {}),
    "holes": ("holes", "area*(1+(x>0))", [], {}),
    "torus": ("torus", "area*(1+(x>0))", ["--torus", "3:1"], {"torus": (3.0, 1.0)}),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_map_equals_the_command_line_bit_for_bit(name, cli, tmp_path, request):
    fixture, population, flags, kwargs = CASES[name]
    v, f = request.getfixturevalue(fixture)
    mesh = tmp_path / f"{name}.obj"
    demkit.write_mesh(mesh, v, f)
    out, report = tmp_path / f"{name}.map.obj", tmp_path / f"{name}.json"
    run = subprocess.run(
        [str(cli), "map", str(mesh), "--out", str(out), "--report", str(report),
         "--population", population, "--quiet", *flags],
        capture_output=True, text=True,
    )
    assert run.returncode in (0, 3), run.stderr
    v_file, f_file = demkit.read_mesh(mesh)
    assert np.array_equal(v_file, v) and np.array_equal(f_file, f)
    m = demkit.map(v_file, f_file, population=population, **kwargs)
    cli_v, cli_f = demkit.read_mesh(out)
    assert m.vertices.dtype == np.float64 and m.vertices.shape == cli_v.shape
    assert np.array_equal(m.vertices.view(np.uint64), cli_v.view(np.uint64))
    assert np.array_equal(m.faces, cli_f)
    cli_report = json.loads(report.read_text())
    assert set(m.report) == set(cli_report)
    assert set(m.report["metrics"]) == set(cli_report["metrics"])
    assert m.report["metrics"] == cli_report["metrics"]
    assert m.report["history"] == cli_report["history"]
    for key in ("method", "input", "converged", "stop_reason", "iterations"):
        assert m.report[key] == cli_report[key], key
    assert set(m.report["time_s"]) == {"init", "map", "total"}
