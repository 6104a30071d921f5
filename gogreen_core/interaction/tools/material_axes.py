"""The material's axes under the brush cursor: which way the fibres, grain or layers will run
before the stroke. :func:`main_axes`: the stiffest direction of the directional Young's modulus
E(d), the stiffest across it, and the third; :func:`cursor_axes` turns them by the frame a
stroke starting there would take (:func:`~gogreen_core.sculpt.material_frame.material_frame_at`).
"""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING, cast

import numpy as np

from gogreen_core.interaction.tools.gauge import tangent_frame
from gogreen_core.physics.material import Material
from gogreen_core.physics.quadrature import lebedev_points
from gogreen_core.sculpt.material_frame import material_frame_at

if TYPE_CHECKING:
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = ["MIN_AXIS", "cursor_axes", "main_axes"]

#: The shortest an axis is drawn, as a fraction of the longest.
MIN_AXIS = 0.3
#: E the same every way within this fraction: isotropic, no axes.
_ISOTROPIC = 1e-6
_ANGLES = 720


@lru_cache(maxsize=8)
def main_axes(material: Material) -> np.ndarray | None:
    """The material's main directions (3, 3), rows: unit directions scaled by E along them
    over the largest E (at least :data:`MIN_AXIS`), right-handed; None for an isotropic
    material (E the same every way). Read-only, cached."""
    nodes = lebedev_points(41)[0]
    young = material.directional_young(nodes)
    top = float(young.max())
    if not young.max() - young.min() > _ISOTROPIC * top:
        return None
    first = nodes[int(np.argmax(young))]
    _, u, v = tangent_frame(first)  # the plane across it
    angles = np.linspace(0.0, np.pi, _ANGLES, endpoint=False)  # ±d is one direction
    ring = np.outer(np.cos(angles), u) + np.outer(np.sin(angles), v)
    second = ring[int(np.argmax(material.directional_young(ring)))]
    third = np.cross(first, second)
    axes = np.array([first, second, third])
    lengths = np.maximum(material.directional_young(axes) / top, MIN_AXIS)
    scaled: np.ndarray = axes * lengths[:, None]
    scaled.setflags(write=False)
    return scaled


def cursor_axes(sculptor: Sculptor, point: np.ndarray, radius: float) -> np.ndarray | None:
    """:func:`main_axes` (3, 3) at ``point`` (3,) on ``sculptor``'s surface for a brush of
    ``radius`` (model units), in the frame a stroke starting there would take, or None."""
    axes = main_axes(sculptor.settings.material)
    if axes is None:
        return None
    frame = material_frame_at(sculptor, point, radius)
    return cast(np.ndarray, axes @ frame.T)
