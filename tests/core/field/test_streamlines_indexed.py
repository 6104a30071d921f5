"""GreenKernel.streamlines on rows of a larger array (``indices``, ``in_place``): bit for bit the
gathered computation, and a failed event leaves the array untouched."""

from __future__ import annotations

import numpy as np
import pytest
from streamline_counts import counted

from gogreen_core import GreenKernel, Material
from gogreen_core._compiled import forced
from gogreen_core.mesh.shapes import default_model
from gogreen_core.physics.radial import GaussianRadial
from gogreen_core.sculpt.brushes import mirror_signs
from gogreen_core.validation import ParameterError


@pytest.fixture(scope="module")
def setup():
    vertices, _ = default_model(4)
    kernel = GreenKernel(Material.cubic(3.0, 1.5, 0.4), 6, GaussianRadial(0.4))
    return vertices, kernel


@pytest.mark.parametrize("tolerance", [1e-8, None])  # 1e-8: many points refined
@pytest.mark.parametrize("affine", [False, True])
def test_indexed_rows_match_the_gathered_points_bit_for_bit(setup, tolerance, affine):
    vertices, kernel = setup
    center = vertices[0].copy()
    load = np.array([[0.0, 0.3, 0.0], [-0.3, 0.0, 0.0], [0.0, 0.0, 0.1]]) if affine else np.ones(3)
    step = np.zeros(3) if affine else np.array([0.02, 0.05, 0.01])
    common = dict(
        center_step=step,
        cutoff=(0.8, 1.6),
        mirror_signs=mirror_signs("x"),
        origin=np.zeros(3),
        tolerance=tolerance,
        substeps=3,
    )
    # unsorted rows, some far apart: the blocks hold other points than the gathered ones would
    rows = np.random.default_rng(0).permutation(len(vertices))[: len(vertices) // 2 + 7]
    gathered, steps = counted(kernel, vertices[rows], center, load, **common)
    indexed, steps_indexed = counted(kernel, vertices, center, load, indices=rows, **common)
    assert np.array_equal(indexed, gathered)
    assert np.array_equal(steps_indexed, steps)
    if tolerance is not None:
        assert steps.max() > 1  # the refinement pass ran on indexed rows too
    buffer = np.full((len(vertices), 3), np.nan)
    mesh = vertices.copy()
    result = kernel.streamlines(mesh, center, load, indices=rows, in_place=True, **common)
    assert np.array_equal(mesh[rows], gathered)
    others = np.setdiff1d(np.arange(len(vertices)), rows)
    assert np.array_equal(mesh[others], vertices[others])
    assert np.array_equal(result, gathered)
    reused, _ = counted(kernel, vertices, center, load, indices=rows, out=buffer, **common)
    assert np.shares_memory(reused, buffer) and np.array_equal(reused, gathered)
    # in place over every row
    whole = vertices.copy()
    kernel.streamlines(whole, center, load, in_place=True, **common)
    assert np.array_equal(whole, kernel.streamlines(vertices, center, load, **common))


def test_indexed_input_errors_name_the_problem_and_move_nothing(setup):
    vertices, kernel = setup
    center = vertices[0].copy()
    mesh = vertices.copy()
    for bad in ([0, len(mesh)], [-1, 2]):
        with pytest.raises(ParameterError, match="indices must be rows") as info:
            kernel.streamlines(mesh, center, np.ones(3), indices=bad, in_place=True)
        assert info.value.parameter == "indices"
    with pytest.raises(ParameterError, match="1-D integers"):
        kernel.streamlines(mesh, center, np.ones(3), indices=[0.5, 1.0])
    poisoned = mesh.copy()
    poisoned[5] = np.nan
    with pytest.raises(ParameterError, match="non-finite"):
        kernel.streamlines(poisoned, center, np.ones(3), indices=[1, 5])
    kernel.streamlines(poisoned, center, np.ones(3), indices=[1, 6])  # row 5 not read
    with pytest.raises(ParameterError, match="writable C-contiguous"):
        kernel.streamlines(mesh[::2], center, np.ones(3), indices=[1], in_place=True)
    # a load so large the end positions overflow (G(0) f beyond 1.8e308): nothing is written
    narrow = kernel.with_radial(GaussianRadial(0.01))
    with pytest.raises(ValueError, match="to infinity"):
        narrow.streamlines(mesh, center, np.full(3, 1.7e308), indices=[0, 1, 2], in_place=True)
    assert np.array_equal(mesh, vertices)
    assert len(kernel.streamlines(mesh, center, np.ones(3), indices=[])) == 0


@pytest.mark.parametrize("tolerance", [1e-4, None])
@pytest.mark.parametrize("indexed", [True, False])
def test_overflowing_ends_write_nothing(setup, tolerance, indexed):
    """The check for non-finite ends runs as the integrator writes them (adaptive and fixed
    steps, rows of a mesh or all of it): an overflow fails the event and moves nothing."""
    vertices, kernel = setup
    narrow = kernel.with_radial(GaussianRadial(0.01))
    mesh = vertices.copy()
    rows = np.arange(0, len(mesh), 7) if indexed else None
    load = np.full(3, 1.7e308)
    with pytest.raises(ValueError, match="to infinity"):
        narrow.streamlines(
            mesh, mesh[0], load, indices=rows, in_place=True, tolerance=tolerance, substeps=2
        )
    assert np.array_equal(mesh, vertices)


@pytest.mark.parametrize("tolerance", [1e-2, None])  # third-order (a few refined), fixed steps
@pytest.mark.parametrize("affine", [False, True])
def test_vouched_rows_are_written_as_made_bit_for_bit(setup, tolerance, affine):
    """``rows_checked``: the ends written in place as the compiled passes make them (none
    through the result buffer but the refined ones') are bit for bit those of the write after
    them; a load whose velocity is not provably bounded takes the checked write (an overflow
    moves nothing, the NumPy twin's too)."""
    vertices, kernel = setup
    affine_load = np.array([[0.0, 0.3, 0.0], [-0.3, 0.0, 0.0], [0.0, 0.0, 0.1]])
    load = affine_load if affine else np.full(3, 0.1)
    rows = np.flatnonzero(vertices[:, 2] > -0.5)  # over THIRD_ORDER_POINTS: probed
    common = dict(
        center_step=np.array([0.02, 0.05, 0.01]), cutoff=(0.4, 0.8), indices=rows,
        tolerance=tolerance, in_place=True,
    )  # fmt: skip
    meshes, outs = [vertices.copy(), vertices.copy()], [np.zeros((len(rows), 3)) for _ in "ab"]
    with forced("generic"):  # (the NumPy twin writes after the passes)
        for mesh, out, checked in zip(meshes, outs, (False, True), strict=True):
            kernel.streamlines(mesh, vertices[0], load, rows_checked=checked, out=out, **common)
    assert not np.array_equal(meshes[0], vertices)
    assert np.array_equal(meshes[1], meshes[0])
    through_result = np.any(outs[1] != 0.0, axis=1)
    assert not through_result.all()  # written as made
    assert through_result.any() == (tolerance is not None)  # the refined rows' ends
    narrow = kernel.with_radial(GaussianRadial(0.01))
    huge = np.full((3, 3) if affine else 3, 1.7e308)
    for code in ("generic", "numpy"):
        mesh = vertices.copy()
        with forced(code), pytest.raises(ValueError, match="to infinity"):
            narrow.streamlines(mesh, vertices[rows[0]], huge, rows_checked=True, **common)
        assert np.array_equal(mesh, vertices), code
