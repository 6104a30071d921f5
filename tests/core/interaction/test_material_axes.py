"""The material's axes at the cursor (issue 35): none for an isotropic material; the glyph's
main directions, turned onto the surface with the "surface" frame."""

from types import SimpleNamespace

import numpy as np

from gogreen_core.files.presets import builtin_presets
from gogreen_core.interaction.tools import CursorController
from gogreen_core.interaction.tools.material_axes import MIN_AXIS, cursor_axes, main_axes
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.physics.material import Material
from gogreen_core.sculpt.sculptor import Sculptor

FIBRES = next(p for p in builtin_presets() if p.name == "Fibre composite")


def test_isotropic_has_no_axes_fibres_have_theirs() -> None:
    assert main_axes(Material.isotropic(1.0, 0.3)) is None
    axes = main_axes(FIBRES.material)
    assert axes is not None
    assert abs(axes[0] @ [0.0, 0.0, 1.0]) > 0.999  # the stiffest: the fibres, along z
    assert np.isclose(np.linalg.norm(axes[0]), 1.0)
    assert MIN_AXIS <= np.linalg.norm(axes[1]) < 1.0
    unit = axes / np.linalg.norm(axes, axis=1)[:, None]
    assert np.allclose(unit @ unit.T, np.eye(3), atol=1e-9)


def test_the_axes_follow_the_surface_with_the_surface_frame() -> None:
    vertices, faces = icosphere(4)
    point = vertices[int(np.argmax(vertices @ np.array([1.0, 0.2, 0.1])))]
    normal = point / np.linalg.norm(point)
    for frame in ("world", "surface"):
        sculptor = Sculptor(
            vertices, faces, settings=FIBRES.engine_settings().replace(material_frame=frame)
        )
        axes = cursor_axes(sculptor, point, 0.05 * sculptor.model_size)
        assert axes is not None
        fibre = axes[0] / np.linalg.norm(axes[0])
        if frame == "surface":  # the material's z (the fibres) along the normal there
            assert abs(fibre @ normal) > 0.99
        else:
            assert abs(fibre @ [0.0, 0.0, 1.0]) > 0.999
    measures = dict(radius=0.1, influence=4.0, profile=None, full_radius=None)
    measures |= dict(moving_radius=None, axes=np.eye(3), detail=None)
    tools = SimpleNamespace(
        **{f"_cursor_{name}": lambda *point, v=value: v for name, value in measures.items()}
    )
    cursor = CursorController(tools)
    state = cursor.place(point, normal)
    assert state is not None and np.array_equal(state.axes, np.eye(3))
