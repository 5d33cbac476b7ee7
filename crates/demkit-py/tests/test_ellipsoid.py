"""EDEM and EDEQ from Python: ellipsoid=(a, b, c), the domain's kind and radii, the refusals."""

from __future__ import annotations

import numpy as np
import pytest

import demkit


@pytest.fixture(scope="module")
def stretched():
    v, f = demkit.generate("icosphere", subdivisions=3)
    return v * np.array([1.0, 1.3, 1.8]), f


def residual(vertices, radii):
    return np.abs(((vertices / np.asarray(radii)) ** 2).sum(axis=1) - 1.0).max()


def test_edem_onto_the_surfaces_own_ellipsoid(stretched):
    v, f = stretched
    m = demkit.map(v, f, method="edem", ellipsoid=(1.0, 1.3, 1.8), population="area*(1+z*z)")
    assert m.converged and m.flipped_triangles == 0
    assert m.domain.kind == "ellipsoid"
    assert tuple(m.domain.radii) == (1.0, 1.3, 1.8)
    assert residual(m.vertices, (1.0, 1.3, 1.8)) <= 1e-9
    assert m.metrics["face_density_var_final"] < 0.01 * m.metrics["face_density_var_initial"]


def test_auto_with_an_ellipsoid_is_edem(stretched):
    v, f = stretched
    m = demkit.map(v, f, ellipsoid=(1.0, 1.0, 2.0))
    assert m.report["method"] == "edem"
    assert residual(m.vertices, (1.0, 1.0, 2.0)) <= 1e-9


def test_edeq_chooses_the_radii(stretched):
    v, f = stretched
    m = demkit.map(v, f, method="edeq", ellipsoid=(1.0, 1.0, 1.0))
    a, b, c = m.domain.radii
    assert a == 1.0 and abs(b - 1.3) < 0.1 and abs(c - 1.8) < 0.15
    assert m.flipped_triangles == 0
    assert residual(m.vertices, (a, b, c)) <= 1e-9


@pytest.mark.parametrize("bad", [(0, 1, 1), (-1, 1, 1), (1, float("nan"), 1), (1, 1, float("inf")), (1, 1)])
def test_bad_radii_are_refused(stretched, bad):
    v, f = stretched
    with pytest.raises(demkit.InputError, match="ellipsoid"):
        demkit.map(v, f, method="edem", ellipsoid=bad)


def test_a_disk_is_not_mapped_onto_an_ellipsoid(disk):
    v, f = disk
    with pytest.raises(demkit.InputError, match="genus-0"):
        demkit.map(v, f, method="edem", ellipsoid=(1, 1, 2))
