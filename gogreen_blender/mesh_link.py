"""What the add-on keeps of a Blender mesh between strokes (no bpy): the engine on it and our
own surface index, kept in step with what Blender holds.

Building a :class:`gogreen_core.Sculptor` (its kernels, its mesh's search blocks) and a
surface index costs about a second on a 500k-vertex mesh, and Blender's ``Object.ray_cast``
rebuilds its own search tree after every change of the mesh (half a second there): done at each
stroke or hover, the first press or hover after a stroke would stall. A :class:`MeshLink` is
made once per mesh and topology; before a hover or a stroke :meth:`MeshLink.sync` compares the
positions Blender holds (float32, read in a fraction of a millisecond) with the ones it last
saw, and hands the rows that differ (Blender's own brushes, its undo) to the sculptor and the
index; picks go through :class:`gogreen_core.mesh.geometry.SurfaceIndex`, updated with the rows a
stroke moved. Blender's sculpt mask and hidden vertices hold vertices through the engine's
vertex mask (:meth:`gogreen_core.sculpt.mask.Mask.adopt`): a vertex moves by (1 − mask) of what it
would, a hidden one not at all.

Positions: Blender stores float32; the sculptor works in float64 and at the end of a stroke
takes the rounded values Blender keeps, so each stroke starts from exactly what Blender holds
(as a new sculptor on the mesh would). The brush radius is a fraction of the mesh's size when
the link was made (as in the desktop app, where it is the size at load: brush sizes do not
jump as strokes change the bounding box).
"""

from __future__ import annotations

import numpy as np

from gogreen_core import Sculptor
from gogreen_core.mesh.geometry import SurfaceIndex

from . import engine

__all__ = ["MeshLink", "held_values"]


def held_values(
    count: int, mask: np.ndarray | None = None, hidden: np.ndarray | None = None
) -> np.ndarray:
    """(count,) float64 in [0, 1]: how much each vertex is held, from Blender's sculpt mask
    (``.sculpt_mask``, clipped to [0, 1]) and hidden vertices (``.hide_vert``: held fully);
    either may be None (absent)."""
    held = np.zeros(count)
    if mask is not None:
        held = np.clip(np.nan_to_num(np.asarray(mask, dtype=np.float64)), 0.0, 1.0)
    if hidden is not None:
        held[np.asarray(hidden, dtype=bool)] = 1.0
    return held


class MeshLink:
    """The engine and a surface index on one Blender mesh.

    positions : (N, 3) float32 as Blender holds them; faces : (M, 3) int triangles;
    topology : (L,) int32 face corners' vertices (Blender's ``.corner_vert``), what tells a
    changed topology; settings : the first stroke's :class:`engine.SculptSettings`.

    :attr:`positions` is what Blender holds as far as the link knows (the rows a stroke moved
    are copied in as it goes, so writing the array back is Blender's full update);
    :attr:`builds` counts surface-index builds (the tests check none happens after a stroke).
    """

    builds = 0

    def __init__(
        self,
        positions: np.ndarray,
        faces: np.ndarray,
        topology: np.ndarray,
        settings: engine.SculptSettings,
    ) -> None:
        self.positions = np.array(positions, dtype=np.float32).reshape(-1, 3)
        self.topology = np.array(topology, dtype=np.int32)
        vertices = self.positions.astype(np.float64)
        # one undo step of memory: Blender keeps the undo history
        self.sculptor: Sculptor = engine.make_sculptor(vertices, faces, settings, history_bytes=1)
        self.index = SurfaceIndex(vertices, faces)
        MeshLink.builds += 1
        # the rows the current stroke moved (marks: a union of each event's rows, without the
        # sort a union of index arrays needs, seconds for a stroke of 20 events on 500k)
        self._touched = np.zeros(len(self.positions), dtype=np.bool_)
        self._any_touched = False

    @property
    def model_size(self) -> float:
        return float(self.sculptor.model_size)

    def fits(self, count: int, topology: np.ndarray) -> bool:
        """The link is for a mesh of ``count`` vertices and these face corners."""
        return len(self.positions) == count and np.array_equal(self.topology, topology)

    def sync(self, positions: np.ndarray, held: np.ndarray | None = None) -> int:
        """Take the positions (N, 3) float32 Blender holds now (and how much each vertex is held,
        (N,)): the rows that changed since the link last saw them go to the sculptor and the
        index. Returns how many rows changed."""
        positions = np.asarray(positions, dtype=np.float32).reshape(-1, 3)
        left_open = self.sculptor.in_stroke  # its operator ended without a release
        if left_open:  # Blender's rows hold: the sculptor takes them below
            self.sculptor.cancel_stroke()
            self._touched[:] = False
            self._any_touched = False
        if held is not None:
            self.sculptor.mask.adopt(held)
        if not left_open and np.array_equal(positions, self.positions):
            return 0
        self.positions[:] = positions
        vertices = positions.astype(np.float64)
        rows = self.sculptor.adopt_vertices(vertices)
        self.index.update(vertices, rows)
        return len(rows)

    def use(self, settings: engine.SculptSettings) -> None:
        """Compute with ``settings`` from now on (the scene's, read at each stroke)."""
        self.sculptor.apply_settings(settings.engine_settings)

    def pick(self, origin: np.ndarray, direction: np.ndarray) -> np.ndarray | None:
        """(3,) the first surface point on the ray (object space), or None."""
        hit = self.index.pick(origin, direction)
        return None if hit is None else hit[1]

    # -- a stroke's writes -------------------------------------------------------------------
    def moved(self, rows: np.ndarray) -> None:
        """The sculptor moved ``rows`` (K,): copy them into :attr:`positions` (rounded to
        float32) for Blender."""
        if len(rows):
            # the whole array: a plain copy (0.5 ms for 500k rows) beats a gather of the rows
            # (40 ms for 500k, 2.4 ms for 10k); the others hold what they held
            np.copyto(self.positions, self.sculptor.vertices, casting="same_kind")
            self._touched[rows] = True
            self._any_touched = True

    def stroke_done(self) -> None:
        """After a stroke ended or was cancelled: :attr:`positions` takes the rows it touched
        from the sculptor (as they ended, or back as they were), the sculptor the float32
        values Blender keeps, the index those rows. The caller writes :attr:`positions`."""
        if not self._any_touched:
            return
        rows = np.flatnonzero(self._touched)
        self._touched[rows] = False
        self._any_touched = False
        self.positions[rows] = self.sculptor.vertices[rows]
        vertices = self.positions.astype(np.float64)
        self.sculptor.adopt_vertices(vertices)
        self.index.update(vertices, rows)
