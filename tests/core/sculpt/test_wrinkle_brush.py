"""The folding wrinkle brush (paper Fig. 10; the paper-controls issue, item 1): on a flat sheet
with the shipped "Layered sheet wrinkles" preset a pull of 2 ε folds the surface (sign changes
of the normal displacement between lobes deeper than 10 % of the pull), the grabbed point
follows, the fold count grows with the fold degree, a grab with the same settings folds
nothing, an isotropic material folds nothing, and sessions before version 3, whose ``wrinkle``
was another brush, are refused naming the stroke."""

import json

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Material, Sculptor, builtin_presets
from gogreen_core.mesh.shapes import flat_sheet, icosphere
from gogreen_core.sculpt.brushes import FOLD_DEPTH, fold_weights
from gogreen_core.sculpt.session import parse_session
from gogreen_core.validation import ParameterError

SHEET = flat_sheet()
RADIUS = 0.05  # ε as a fraction of the model size, as in the issue
PRESET = next(p for p in builtin_presets() if p.name == "Layered sheet wrinkles")


def _pull(kind: str, degree: int | None = None, direction=(0.0, 0.0, 1.0), material=None):
    """Displacement (N, 3) and ε of a 10-event stroke moving the cursor 2 ε from the sheet's
    centre along ``direction``, with the preset's settings (and folds of ``degree``)."""
    vertices, faces = SHEET
    # measured with the material's axes fixed in the world (the preset's own frame, "surface",
    # would turn the layers with each drag's direction: tests/core/sculpt/test_material_frame.py)
    settings = PRESET.engine_settings().replace(material_frame="world")
    if material is not None:
        settings = settings.replace(material=material)
    if degree is not None:
        settings = settings.with_brush_weights("wrinkle", fold_weights(settings.l_max, degree))
    sculptor = Sculptor(vertices, faces, settings=settings)
    eps = RADIUS * sculptor.model_size
    step = 0.2 * eps * np.asarray(direction) / np.linalg.norm(direction)
    events = [BrushEvent(k * step, step) for k in range(10)]
    sculptor.apply_brush(Brush(kind, radius=RADIUS), events)
    return sculptor.vertices - vertices, eps


def _ring_folds(displacement: np.ndarray, eps: float, depth: float) -> list[tuple[float, int]]:
    """(ring radius in ε, sign changes of the normal displacement around it between lobes
    deeper than ``depth``) for rings of radius 1 … 5 ε around the centre."""
    vertices = SHEET[0]
    radius = np.linalg.norm(vertices[:, :2], axis=1)
    angle = np.arctan2(vertices[:, 1], vertices[:, 0])
    out = []
    for rho in np.arange(1.0, 5.01, 0.5):
        near = np.abs(radius - rho * eps) < 0.006
        normal = displacement[near, 2][np.argsort(angle[near])]
        signs: list[float] = []
        for value in normal[np.abs(normal) > depth]:
            if not signs or signs[-1] != np.sign(value):
                signs.append(np.sign(value))
        if len(signs) > 1 and signs[0] == signs[-1]:
            signs.pop()  # around a ring the last lobe meets the first
        out.append((float(rho), len(signs) if len(signs) > 1 else 0))
    return out


def _most_folds(displacement: np.ndarray, eps: float) -> int:
    return max(count for _, count in _ring_folds(displacement, eps, 0.1 * 2 * eps))


def _follows(displacement: np.ndarray, eps: float, direction=(0.0, 0.0, 1.0)) -> float:
    """How far the vertex under the cursor moved along the pull, as a fraction of it."""
    centre = int(np.argmin(np.linalg.norm(SHEET[0], axis=1)))
    unit = np.asarray(direction) / np.linalg.norm(direction)
    return float(displacement[centre] @ unit / (2 * eps))


ACROSS = (0.0, 1.0, 0.0)  # a drag along the surface, across the layers' trace on it


@pytest.fixture(scope="module")
def pulls():
    return (
        {degree: _pull("wrinkle", degree) for degree in (6, 8, 10)}
        | {("across", d): _pull("wrinkle", d, direction=ACROSS) for d in (6, 8, 10)}
        | {"grab": _pull("grab"), "preset": _pull("wrinkle")}
    )


def _turned(displacement: np.ndarray) -> int:
    """Faces of the sheet the stroke turned over."""
    vertices, faces = SHEET

    def normals(v: np.ndarray) -> np.ndarray:
        return np.cross(v[faces[:, 1]] - v[faces[:, 0]], v[faces[:, 2]] - v[faces[:, 0]])

    flipped = np.einsum("ij,ij->i", normals(vertices), normals(vertices + displacement)) <= 0
    return int(np.sum(flipped))


def test_the_shipped_preset_folds_a_sheet_and_the_grabbed_point_follows(pulls):
    displacement, eps = pulls["preset"]
    assert _most_folds(displacement, eps) >= 4  # measured 8 on the ring at 3 ε
    # lobes on both sides of the sheet, each deeper than 10 % of the pull
    assert displacement[:, 2].min() < -0.1 * 2 * eps  # measured −0.16 of the pull
    assert _follows(displacement, eps) >= 0.25  # measured 0.69
    assert _turned(displacement) == 0


def test_a_grab_with_the_same_settings_folds_nothing(pulls):
    displacement, eps = pulls["grab"]
    assert _most_folds(displacement, eps) == 0
    assert displacement[:, 2].min() > -0.01 * 2 * eps
    assert _follows(displacement, eps) > 0.99


def test_more_folds_for_a_higher_fold_degree(pulls):
    """Dragged across the layers, degrees 6, 8, 10 fold the sheet 6, 8, 10 times around the
    brush (measured); pulled along the normal every degree folds it at least 4 times (8, 8, 6:
    the slope limit holds degree 10 back, which turned 42 faces over without it, 5 with)."""
    across = [_most_folds(*pulls[("across", degree)]) for degree in (6, 8, 10)]
    assert across[0] < across[1] < across[2], across
    for degree in (6, 8, 10):
        assert _most_folds(*pulls[degree]) >= 4, degree
        assert _follows(*pulls[degree]) >= 0.25
    for key in (6, 8, ("across", 6), ("across", 8), ("across", 10)):
        assert _turned(pulls[key][0]) == 0, key


@pytest.mark.parametrize("direction", [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0)])
def test_a_drag_along_the_surface_folds_too(direction):
    displacement, eps = _pull("wrinkle", direction=direction)
    # measured 8 sign changes for both; the grabbed point follows all the way
    assert _most_folds(displacement, eps) >= 4
    assert _follows(displacement, eps, direction) > 0.95
    assert _turned(displacement) == 0


def test_an_isotropic_material_folds_nothing():
    """An isotropic material has no degree above 2: the wrinkle brush is then a pull, the same
    with or without fold weights."""
    iso = Material.isotropic(1.0, 0.3)
    folded, eps = _pull("wrinkle", 8, material=iso)
    vertices, faces = SHEET
    settings = PRESET.engine_settings().replace(material=iso)
    flat = settings.with_brush_weights(
        "wrinkle", fold_weights(settings.l_max, 8) * (np.arange(12) < 4)
    )
    sculptor = Sculptor(vertices, faces, settings=flat)
    step = np.array([0.0, 0.0, 0.2 * eps])
    sculptor.apply_brush(
        Brush("wrinkle", radius=RADIUS), [BrushEvent(k * step, step) for k in range(10)]
    )
    assert np.abs((sculptor.vertices - vertices) - folded).max() < 1e-12 * eps
    assert _most_folds(folded, eps) == 0


def test_fold_weights_pick_one_degree():
    omega = fold_weights(10, 6)
    assert omega.shape == (12,)
    assert list(np.flatnonzero(omega)) == [0, 2, 6] and omega[6] == FOLD_DEPTH
    assert list(np.flatnonzero(fold_weights(8, 10))) == [0, 2, 8]  # capped at l_max
    assert list(np.flatnonzero(fold_weights(3))) == [0, 2]  # no degree ≥ 4: no folds
    assert fold_weights(10, 8, depth=1.5)[8] == 1.5


def test_an_old_sessions_wrinkle_stroke_is_refused_naming_it():
    """A version-2 session's ``wrinkle`` stroke was the brush of that time, which no longer
    exists: the file is refused naming the stroke, not replayed with the folding brush."""
    vertices, faces = icosphere(2)
    sculptor = Sculptor(vertices, faces, material=PRESET.material)
    sculptor.apply_brush(Brush("grab", radius=0.2), [BrushEvent(vertices[5], [0.0, 0.02, 0.0])])
    sculptor.apply_brush(Brush("wrinkle", radius=0.2), [BrushEvent(vertices[5], [0.0, 0.02, 0.0])])
    session = json.loads(json.dumps(sculptor.session()))
    assert Sculptor.from_session(session, vertices, faces) is not None  # today's: replayed
    old = dict(session, version=2)
    with pytest.raises(ParameterError, match=r"operations\[1\] is a stroke of the wrinkle"):
        Sculptor.from_session(old, vertices, faces)


def test_wrinkle_weights_live_in_the_settings_and_replay():
    vertices, faces = icosphere(3)
    sculptor = Sculptor(vertices, faces, settings=PRESET.engine_settings())
    assert np.array_equal(sculptor.settings.weights_for("wrinkle"), fold_weights(10, 8))
    sculptor.apply_settings(sculptor.settings.with_brush_weights("wrinkle", fold_weights(10, 10)))
    sculptor.apply_brush(Brush("wrinkle", radius=0.1), [BrushEvent(vertices[7], [0.0, 0.0, 0.03])])
    session = json.loads(json.dumps(sculptor.session()))
    assert session["operations"][0]["brush_weights"]["wrinkle"][10] == FOLD_DEPTH
    again = Sculptor.from_session(session, vertices, faces)
    again.replay(parse_session(session))
    assert np.array_equal(again.vertices, sculptor.vertices)
    sculptor.undo()
    sculptor.undo()  # the weights too
    assert np.array_equal(sculptor.settings.weights_for("wrinkle"), fold_weights(10, 8))
