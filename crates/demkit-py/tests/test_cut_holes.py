"""demkit.cut_holes: the command line's `demkit cut`, numpy in and out."""

from __future__ import annotations

import numpy as np
import pytest

import demkit


def boundary_loops(f):
    """The number of boundary loops of the faces f (edges used once, chained)."""
    edges = {}
    for a, b, c in f:
        for u, w in ((a, b), (b, c), (c, a)):
            key = (min(u, w), max(u, w))
            edges[key] = edges.get(key, 0) + 1
    nxt = {}
    for (u, w), count in edges.items():
        if count == 1:
            nxt.setdefault(u, []).append(w)
            nxt.setdefault(w, []).append(u)
    seen, loops = set(), 0
    for start in nxt:
        if start in seen:
            continue
        loops += 1
        stack = [start]
        while stack:
            v = stack.pop()
            if v not in seen:
                seen.add(v)
                stack.extend(nxt[v])
    return loops


def test_two_holes_make_three_loops_and_deq_maps_them():
    v, f = demkit.generate("polygon", sides=6, rings=24)
    cv, cf = demkit.cut_holes(v, f, holes=[(0.4, 0, 0, 0.15), (-0.4, 0.1, 5, 0.2)], planar=True)
    assert cv.dtype == np.float64 and cf.dtype == np.int64
    assert len(cf) < len(f) and boundary_loops(cf) == 3
    # The kept vertices keep their input order: they are a subsequence of the input's.
    rows = [tuple(p) for p in v]
    at = [rows.index(tuple(p)) for p in cv]
    assert at == sorted(at)
    m = demkit.map(cv, cf, method="deq")
    assert m.flipped_triangles == 0
    # A ball instead of a cylinder: the second centre lies 5 above the disk and cuts nothing.
    _, bf = demkit.cut_holes(v, f, holes=[(0.4, 0, 0, 0.15), (-0.4, 0.1, 5, 0.2)])
    assert boundary_loops(bf) == 2


@pytest.mark.parametrize(
    "holes",
    [[], [(0, 0, 0)], [(0, 0, 0, "x")], [(0, 0, 0, -1)], [(np.nan, 0, 0, 0.1)], [(0, 0, 0, 100)]],
)
def test_bad_holes_are_input_errors(holes):
    v, f = demkit.generate("polygon", sides=6, rings=6)
    with pytest.raises(demkit.InputError):
        demkit.cut_holes(v, f, holes=holes, planar=True)
