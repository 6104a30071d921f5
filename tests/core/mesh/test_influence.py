"""The influence test answered with the boxes of vertex blocks (``gogreen_core.mesh.influence``)
gives the rows of the plain pass over every vertex (``_evaluation.near_segment`` +
``np.flatnonzero``) exactly, for every query and after every kind of vertex write, with the NumPy
with the compiled code (NumPy, until it is ready, answers by the plain pass and marks the
writes). (The conftest also checks every ``rows_near`` answer of every test against
the plain pass.)
"""

from __future__ import annotations

import threading

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Sculptor, _compiled
from gogreen_core.field import _evaluation, _influence_compiled
from gogreen_core.mesh import influence
from gogreen_core.mesh.mesh_state import MeshState
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.brushes import mirror_signs
from gogreen_core.sculpt.sculptor import capture_state, restore_state

CODES = ("unrolled",)
SYMMETRIES = ("", "x", "xz", "xyz")


def plain(mesh, center, step, radius, signs):
    """The rows of the plain pass, as ``MeshState.rows_near`` gave them before the blocks."""
    reach = np.empty(len(mesh.vertices), dtype=bool)
    _evaluation.near_segment(mesh.vertices, center, step, radius, signs, mesh.origin, reach)
    return np.flatnonzero(reach)


def bumpy_sphere(subdivisions=4):
    """A lumpy icosphere whose vertices are listed in Morton order (locality, as in most mesh
    files; the icosphere's own order has little)."""
    vertices, faces = icosphere(subdivisions)
    bumps = 1.0 + 0.2 * np.sin(4 * vertices[:, 0]) * np.cos(3 * vertices[:, 1])
    vertices = vertices * bumps[:, None] * [1.3, 1.0, 0.8] + [0.4, -0.2, 0.1]
    q = ((vertices - vertices.min(axis=0)) * (1023 / np.ptp(vertices, axis=0).max())).astype(int)
    code = np.zeros(len(vertices), dtype=np.int64)
    for bit in range(10):
        for k in range(3):
            code |= ((q[:, k] >> bit) & 1) << (3 * bit + k)
    order = np.argsort(code, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return vertices[order], rank[faces]


def with_far_rows(points, n=20_000):
    """``points`` and, after them, a line of ``n`` rows far away (queries near ``points`` then
    test few rows: the blocks answer, not the plain pass)."""
    far = points.max(axis=0) + 100.0 + np.linspace(0.0, 10.0, n)[:, None] * [1.0, 0.5, 0.2]
    return MeshState(np.vstack([points, far]), np.zeros((0, 3), dtype=np.int64))


def random_query(rng, mesh):
    """A centre near (or far from) the surface, a step (zero, short or long), a radius (tiny to
    the whole model) and a symmetry."""
    size = mesh.model_size
    kind = rng.integers(6)
    if kind == 0:  # off the mesh: the cursor far away
        center = mesh.origin + rng.normal(size=3) * 3 * size
    else:
        center = mesh.vertices[rng.integers(len(mesh.vertices))] + rng.normal(size=3) * 0.02 * size
    step = [np.zeros(3), 0.01 * size * rng.normal(size=3), 0.5 * size * rng.normal(size=3)][
        rng.integers(3)
    ]
    radius = size * 10 ** rng.uniform(-4, 0.5)
    return center, step, radius, mirror_signs(SYMMETRIES[rng.integers(4)])


def assert_rows_right(mesh, rng, queries=12, around=None):
    """rows_near == the plain pass for random queries (and ones centred on ``around`` rows)."""
    used = mesh._blocks.answers["blocks"]
    for i in range(queries):
        center, step, radius, signs = random_query(rng, mesh)
        if around is not None and len(around) and i % 2:
            center = mesh.vertices[around[rng.integers(len(around))]]
        got = mesh.rows_near(center, step, radius, signs)
        assert got.dtype == np.int64
        np.testing.assert_array_equal(got, plain(mesh, center, step, radius, signs))
    assert mesh._blocks.answers["blocks"] > used  # the blocks answered, not only the plain pass


def classified(mesh, start, step, radius, signs, python=False):
    """(blocks a capsule may reach, blocks taken whole) (n_blocks,) by the box tests (their
    Python source if ``python``: it reads a patched SLACK), on the boxes of ``mesh``'s last
    query."""
    blocks = mesh._blocks
    query = (start, step, radius, signs, mesh.origin)
    n_blocks = len(blocks._lo)
    status, images = np.empty(n_blocks, np.uint8), np.empty(n_blocks, np.uint8)
    hits = np.empty(n_blocks, np.int64)
    classify = _influence_compiled._classify
    (classify.py_func if python else classify)(
        blocks._lo, blocks._hi, len(mesh.vertices), *query, status, images, hits
    )
    return status != _influence_compiled.OUT, status == _influence_compiled.INSIDE


@pytest.mark.parametrize("code", CODES)
def test_random_queries_give_the_plain_rows(code):
    rng = np.random.default_rng(1)
    mesh = MeshState(*bumpy_sphere(5))
    with _compiled.forced(code):
        assert_rows_right(mesh, rng, queries=120)
        assert mesh.rows_near(mesh.origin, np.zeros(3), None, mirror_signs("")).tolist() == list(
            range(len(mesh.vertices))
        )


@pytest.mark.parametrize("code", CODES)
def test_points_at_rounding_distance_from_the_capsule(code):
    """Far from the origin (large coordinates: the largest rounding): shells of points within
    rounding of the capsule's surface (blocks tested point by point, where another per-point
    arithmetic would decide differently), and blocks of points in tiny patches at 3 margins
    inside and outside it (taken whole, and skipped: the margin is no wider than it says)."""
    rng = np.random.default_rng(7)
    start, step, radius = np.array([3.0e3, -2.0e3, 1.0e3]), np.array([0.3, -0.1, 0.2]), 0.7
    origin = np.array([2.9e3, -2.1e3, 0.9e3])
    # the margin: SLACK times the largest coordinate (the far rows' ~3.2e3)
    margin = _influence_compiled.SLACK * 3.2e3

    def sphere_points(count, distance, spread):
        direction = rng.normal(size=3) + spread * rng.normal(size=(count, 3))
        direction /= np.linalg.norm(direction, axis=1)[:, None]
        return start + distance * direction  # about the segment's start: the capsule's cap

    shells = [
        sphere_points(4096, radius * (1.0 + relative), 1e3)
        for relative in (-1e-9, -1e-12, -1e-15, 0.0, 1e-15, 1e-12, 1e-9)
    ]
    inside = [sphere_points(64, radius - 3 * margin, 1e-10) for _ in range(8)]
    outside = [sphere_points(64, radius + 3 * margin, 1e-10) for _ in range(8)]
    points = np.vstack([*shells, *inside, *outside])
    mesh = with_far_rows(points, 100_000)
    mesh.origin = origin
    zero, signs = np.zeros(3), mirror_signs("")
    with _compiled.forced(code):
        for symmetry in SYMMETRIES:
            for s in (step, zero):
                got = mesh.rows_near(start, s, radius, mirror_signs(symmetry))
                expected = plain(mesh, start, s, radius, mirror_signs(symmetry))
                np.testing.assert_array_equal(got, expected)
                assert 0 < len(expected) < len(points)
        assert mesh._blocks.answers == {"blocks": 8, "plain": 0}
    # the blocks of the patches: 8 inside, then 8 outside
    patches = np.arange(len(shells) * 4096 // 64, len(points) // 64)
    reached, whole = classified(mesh, start, zero, radius, signs)
    assert whole[patches[:8]].all()
    assert not reached[patches[8:]].any()


def test_the_margin_is_what_keeps_the_rows_exact(monkeypatch):
    """Without its margin, the box test skips (or takes whole) a block of points within
    rounding of the capsule's surface, some of which pass (fail) the per-point test: the tests
    above can fail."""
    start, radius = np.array([1.0e4, 1.0e4, 1.0e4]), 1.0
    direction = np.array([1.0, 2.0, 2.0]) / 3.0
    ulp = np.spacing(1.0e4)
    points = start + (radius + ulp * np.arange(-32, 32))[:, None] * direction  # one block
    mesh = with_far_rows(points)
    signs, zero = mirror_signs(""), np.zeros(3)
    expected = plain(mesh, start, zero, radius, signs)
    assert 0 < len(expected) < 64
    with _compiled.forced("unrolled"):
        np.testing.assert_array_equal(mesh.rows_near(start, zero, radius, signs), expected)
        assert mesh._blocks.answers == {"blocks": 1, "plain": 0}
    reached, whole = classified(mesh, start, zero, radius, signs, python=True)
    assert reached[0] and not whole[0]  # tested point by point
    monkeypatch.setattr(_influence_compiled, "SLACK", -1e-14)  # a margin of -1e-10 here
    reached, whole = classified(mesh, start, zero, radius, signs, python=True)
    assert not reached[0] or whole[0]


def test_writes_while_numpy_serves_are_marked_for_the_compiled_blocks():
    """Before the compiled code is ready the plain pass answers and writes only mark their
    blocks (negative rows from the end); the compiled blocks then answer right."""
    rng = np.random.default_rng(13)
    mesh = MeshState(*bumpy_sphere(4))
    n = len(mesh.vertices)
    with _compiled.forced("unrolled"):
        assert_rows_right(mesh, rng, queries=3)
    by_blocks = mesh._blocks.answers["blocks"]
    with _compiled.forced("numpy"):
        for rows in (np.arange(5), np.arange(-40, -10)):
            mesh.vertices[rows] = mesh.vertices[rng.integers(n)] + 0.01  # in place, reported
            mesh.moved(rows)
            center, step, radius, signs = random_query(rng, mesh)
            got = mesh.rows_near(center, step, radius, signs)
            np.testing.assert_array_equal(got, plain(mesh, center, step, radius, signs))
        assert mesh._blocks.answers["blocks"] == by_blocks and mesh._blocks._dirty.sum() >= 2
    with _compiled.forced("unrolled"):
        assert_rows_right(mesh, rng, queries=8, around=np.arange(5))


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")  # |step|² = inf
@pytest.mark.parametrize("code", CODES)
def test_queries_the_blocks_leave_to_the_plain_pass(code):
    rng = np.random.default_rng(5)
    vertices, faces = bumpy_sphere(4)
    shuffled = MeshState(vertices[rng.permutation(len(vertices))], faces)  # no locality at all
    mesh = MeshState(vertices, faces)
    center, zero = vertices[0], np.zeros(3)
    queries = [
        (mesh, center, zero, np.nan, mirror_signs("")),  # NaN radius: nothing
        (mesh, center, zero, 1e-200, mirror_signs("")),  # a radius whose square underflows
        (mesh, center, np.full(3, 1e-130), 0.5, mirror_signs("x")),  # |step|² underflows
        (mesh, center, np.full(3, 1e160), 0.5, mirror_signs("x")),  # |step|² overflows
        (mesh, center, zero, 0.5, np.array([[1.0, 1.0, 1.0], [0.5, 1.0, 1.0]])),  # not ±1
        (mesh, center, zero, 0.5, np.ones((9, 3))),  # more than 8 images
        (shuffled, center, zero, 0.5, mirror_signs("")),  # every block spans the model
    ]
    with _compiled.forced(code):
        for state, c, step, radius, signs in queries:
            got = state.rows_near(c, step, radius, signs)
            np.testing.assert_array_equal(got, plain(state, c, step, radius, signs))
        assert mesh._blocks.answers == {"blocks": 0, "plain": 6}
        assert shuffled._blocks.answers == {"blocks": 0, "plain": 1}
        huge = MeshState(vertices * 1e152, faces)  # coordinates past the margin argument's
        c = huge.vertices[0]
        np.testing.assert_array_equal(
            huge.rows_near(c, np.zeros(3), 1e140, mirror_signs("")),
            plain(huge, c, np.zeros(3), 1e140, mirror_signs("")),
        )
        assert huge._blocks.answers == {"blocks": 0, "plain": 1}
        # a radius covering the whole model: every block taken whole, no per-point test
        assert_rows_right(mesh, rng, queries=2)
        every = mesh.rows_near(center, zero, 10 * mesh.model_size, mirror_signs("xyz"))
        assert len(every) == len(vertices)


@pytest.mark.parametrize("code", CODES)
def test_a_vertex_order_without_locality_is_left_to_the_plain_pass(code, monkeypatch):
    """Shuffled rows: every block spans the model, the index goes dormant (no upkeep of its
    writes, the plain pass answers); a new array with locality is served by blocks again."""
    monkeypatch.setattr(influence, "VERIFY", False)  # (which keeps every index awake)
    rng = np.random.default_rng(29)
    vertices, faces = bumpy_sphere(5)
    order = rng.permutation(len(vertices))
    mesh = MeshState(vertices[order], faces[:0])
    with _compiled.forced(code):
        for _ in range(3):
            center, step, radius, signs = random_query(rng, mesh)
            got = mesh.rows_near(center, step, radius, signs)
            np.testing.assert_array_equal(got, plain(mesh, center, step, radius, signs))
            rows = rng.integers(0, len(vertices), 100)
            mesh.write_rows(rows, mesh.vertices[rows] + 0.1)
            assert mesh._blocks._dirty.sum() == 0  # not tracked
        assert mesh._blocks.answers == {"blocks": 0, "plain": 3}
        snapshot = mesh.snapshot()
        mesh.adopt(type(snapshot)(vertices, snapshot.faces, snapshot.mask))
        assert_rows_right(mesh, rng, queries=8)
        assert mesh._blocks._dormant is False


@pytest.mark.parametrize("code", CODES)
def test_vertices_moved_out_of_their_block_are_found(code):
    """Rows moved far from their block's other rows (written with ``write_rows`` or in place
    and reported with ``moved``), and moved back: every query, around the old and the new
    places, gives the plain pass's rows."""
    rng = np.random.default_rng(11)
    mesh = MeshState(*bumpy_sphere(4))
    n = len(mesh.vertices)
    with _compiled.forced(code):
        assert_rows_right(mesh, rng, queries=4)  # the boxes are built
        for round_ in range(12):
            rows = np.unique(rng.integers(0, n, size=rng.integers(1, 300)))
            target = mesh.vertices[rng.integers(n)]
            new = target + 0.01 * rng.normal(size=(len(rows), 3))
            if round_ % 3 == 0:
                mesh.write_rows(rows, new)
            elif round_ % 3 == 1:
                mesh.vertices[rows] = new  # in place, then reported
                mesh.moved(rows)
            else:
                mesh.vertices[rows - n] = new  # negative indices, as numpy takes them
                mesh.moved(rows - n)
            assert_rows_right(mesh, rng, queries=8, around=rows)
        mesh.vertices[:] = mesh.vertices[::-1].copy()  # every row: reported as None
        mesh.moved(None)
        assert_rows_right(mesh, rng, queries=8)


@pytest.mark.parametrize("code", CODES)
def test_an_answer_reported_back_marks_its_blocks_without_a_row_pass(code, monkeypatch):
    """A brush event reports the rows ``rows_near`` gave it (the same array): their blocks are
    marked from the answer's blocks, not by a pass over the rows, and later queries around
    where they went give the plain pass's rows; another array of the same rows takes the pass."""
    rng = np.random.default_rng(5)
    mesh = MeshState(*bumpy_sphere(4))
    signs = mirror_signs("x")
    passes = []
    mark = influence._mark
    monkeypatch.setattr(influence, "_mark", lambda *a: passes.append(1) or mark(*a))
    with _compiled.forced(code):
        for round_ in range(6):
            center = mesh.vertices[rng.integers(len(mesh.vertices))]
            rows = mesh.rows_near(center, np.zeros(3), 0.3, signs)
            assert len(rows)
            mesh.vertices[rows] += 0.2 * rng.normal(size=3)  # a shift of a few blocks' size
            mesh.moved(rows if round_ % 2 == 0 else rows.copy())
            assert len(passes) == round_ // 2 + round_ % 2
            assert_rows_right(mesh, rng, queries=6, around=rows)


def test_an_unreported_write_is_caught():
    """What the conftest's check is for: a write that forgets to report its rows gives wrong
    rows, and the check says so."""
    mesh = MeshState(*bumpy_sphere(4))
    center, zero, signs = mesh.vertices[0].copy(), np.zeros(3), mirror_signs("")
    with _compiled.forced("unrolled"):
        before = mesh.rows_near(center, zero, 0.1, signs)
        far = np.flatnonzero(np.linalg.norm(mesh.vertices - center, axis=1) > 1.0)[:5]
        mesh.vertices[far] = center  # not reported
        with pytest.raises(AssertionError, match="stale vertex blocks"):
            mesh.rows_near(center, zero, 0.1, signs)
        influence.mismatches.clear()
        mesh.moved(far)
        np.testing.assert_array_equal(
            mesh.rows_near(center, zero, 0.1, signs), np.union1d(before, far)
        )


@pytest.mark.parametrize("code", CODES)
def test_a_new_vertex_array_is_indexed_anew(code):
    rng = np.random.default_rng(2)
    mesh = MeshState(*bumpy_sphere(4))
    with _compiled.forced(code):
        assert_rows_right(mesh, rng, queries=3)
        snapshot = mesh.snapshot()
        moved = snapshot.vertices[::-1].copy()
        mesh.adopt(type(snapshot)(moved, snapshot.faces, snapshot.mask))  # no report needed
        assert_rows_right(mesh, rng, queries=6)
        mesh.vertices = mesh.vertices + 0.3  # even a plain assignment of another array
        assert_rows_right(mesh, rng, queries=6)


def _sculpt_everything(sculptor, rng):
    """Every engine path that writes vertices, each followed by a check of ``rows_near``."""
    mesh = sculptor._mesh
    size = sculptor.model_size
    top = mesh.vertices[int(np.argmax(mesh.vertices[:, 2]))].copy()
    side = mesh.vertices[int(np.argmax(mesh.vertices[:, 0]))].copy()
    drag = np.array([0.3, 0.2, 0.9]) * 0.05 * size

    def check():
        assert_rows_right(mesh, rng, queries=6, around=np.flatnonzero(moved_rows))

    moved_rows = np.zeros(len(mesh.vertices), dtype=bool)
    # a grab stroke written through by the integrator, with a mirror image
    brush = Brush("grab", radius=0.15, influence=2.0, symmetry="x")
    sculptor.begin_stroke(brush)
    for k in range(3):
        moved_rows[sculptor.stroke_event(BrushEvent(top + k * drag, drag))] = True
        check()
    sculptor.end_stroke()
    # a stroke cancelled half-way
    sculptor.begin_stroke(Brush("twist", radius=0.2))
    sculptor.stroke_event(BrushEvent(side, amount=0.3, axis=[1.0, 0, 0], direction=[0, 1.0, 0]))
    check()
    sculptor.cancel_stroke()
    check()
    # smooth: the driver writes the rows
    sculptor.apply_brush(Brush("smooth", radius=0.2, strength=3.0), [BrushEvent(top, drag)])
    check()
    # a masked grab: the driver blends and writes
    sculptor.apply_brush(Brush("mask", radius=0.2), [BrushEvent(side, np.zeros(3))])
    sculptor.apply_brush(Brush("grab", radius=0.2), [BrushEvent(side, -drag)])
    check()
    sculptor.mask.clear()
    # pins: a drag moves the rows within the pins' reach
    pin = sculptor.add_constraint(side)
    sculptor.add_constraint(top)
    sculptor.drag_constraint(pin, 0.05 * size * np.array([0.0, 1.0, 0.0]))
    check()
    # undo and redo of everything so far, then again
    while sculptor.undo() is not None:
        check()
    while sculptor.redo() is not None:
        check()
    # a subdivision (a new array), sculpted on, undone, redone
    sculptor.subdivide()
    moved_rows = np.zeros(len(mesh.vertices), dtype=bool)
    moved_rows[sculptor.apply_brush(Brush("pinch", radius=0.2), [BrushEvent(top, amount=0.4)])] = 1
    check()
    sculptor.undo()
    check()
    sculptor.undo()
    moved_rows = np.zeros(len(mesh.vertices), dtype=bool)
    check()
    sculptor.redo()
    check()


@pytest.mark.parametrize("code", CODES)
def test_every_engine_write_keeps_the_rows_right(code):
    rng = np.random.default_rng(17)
    vertices, faces = bumpy_sphere(3)
    with _compiled.forced(code):
        sculptor = Sculptor(vertices, faces)
        _sculpt_everything(sculptor, rng)
        # the session replayed (a replay that fails part-way rolls back through adopt)
        replayed = Sculptor.from_session(sculptor.session(), vertices, faces)
        replayed.replay(sculptor.session()["operations"])
        np.testing.assert_array_equal(replayed.vertices, sculptor.vertices)
        assert_rows_right(replayed._mesh, rng, queries=6)
        # a replay failing part-way (an event off the model) is rolled back (adopt)
        before = replayed.vertices.copy()
        grab = {"kind": "grab", "radius": 0.2, "strength": 1.0, "influence": 2.0}
        event = {"center": before[0].tolist(), "delta": [0.05, 0.0, 0.0]}
        broken = [
            {"op": "stroke", "brush": grab, "events": [event, {**event, "center": [1e9] * 3}]}
        ]
        with pytest.raises(ValueError, match="too far"):
            replayed.replay(broken)
        np.testing.assert_array_equal(replayed.vertices, before)
        assert_rows_right(replayed._mesh, rng, queries=6)
        # a recovered state
        restored = restore_state(capture_state(sculptor), sculptor.faces)
        assert_rows_right(restored._mesh, rng, queries=6)


def test_a_background_query_and_writes_interleave():
    """A thread asking while another writes and reports: afterwards the answers are right."""
    rng = np.random.default_rng(23)
    mesh = MeshState(*bumpy_sphere(4))
    n, stop = len(mesh.vertices), threading.Event()
    errors = []

    def ask():
        try:
            while not stop.is_set():
                mesh.rows_near(mesh.vertices[0], np.zeros(3), 0.3, mirror_signs("x"))
        except Exception as exc:  # pragma: no cover - reported below
            errors.append(exc)

    with _compiled.forced("unrolled"):
        thread = threading.Thread(target=ask)
        thread.start()
        try:
            for _ in range(200):
                rows = np.unique(rng.integers(0, n, size=50))
                mesh.write_rows(
                    rows, mesh.vertices[rng.integers(n)] + 0.01 * rng.random((50, 3))[: len(rows)]
                )
        finally:
            stop.set()
            thread.join()
        assert not errors
        assert_rows_right(mesh, rng, queries=10)


@pytest.mark.parametrize("code", CODES)
def test_a_pin_drag_by_the_blocks_moves_what_the_plain_pass_would(code):
    one, faces = bumpy_sphere(4)
    # two lumps apart: a pin's reach (a fraction of the model) holds one and not the other
    vertices = np.vstack([one, one + np.array([12.0, 0.0, 0.0])])
    faces = np.vstack([faces, faces + len(one)])
    with _compiled.forced(code):
        sculptor = Sculptor(vertices, faces)
        mesh = sculptor._mesh
        pins = sculptor._pins
        for point in (mesh.vertices[0], mesh.vertices[len(vertices) // 2]):
            sculptor.add_constraint(point)
        constraints = pins.constraints
        targets = np.zeros((2, 3))
        targets[0] = 0.03 * sculptor.model_size
        forces = constraints.solve(targets)

        def blocks(p, r):
            return mesh.rows_near(p, np.zeros(3), r, np.ones((1, 3)))

        def plain(p, r):
            return np.flatnonzero(np.linalg.norm(mesh.vertices - p, axis=1) <= r)

        by_blocks = constraints.displacement_rows(mesh.vertices, forces, blocks)
        by_plain = constraints.displacement_rows(mesh.vertices, forces, plain)
        assert 0 < len(by_blocks[0]) < len(vertices)  # a real ball, not every vertex
        assert mesh._blocks.answers["blocks"] >= 1  # the blocks answered, not the plain pass
        np.testing.assert_array_equal(by_blocks[0], by_plain[0])
        np.testing.assert_array_equal(by_blocks[1], by_plain[1])
