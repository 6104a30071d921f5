"""QPainter previews of a periodic two-phase voxel cell: an isometric block view and three
orthogonal slices.

The isometric view draws the stiff phase b as solid voxels seen from the (+x, +y, +z) corner
(faces coloured by orientation, like a sunlit block) inside the wireframe of the cell, so an
artist reads layers, fibres, spheres or a lattice at a glance. The slices show one plane of
each orientation at an adjustable depth.
"""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QEvent, QPointF, QRectF, QSize, Qt
from PySide6.QtGui import (
    QColor,
    QFont,
    QImage,
    QPainter,
    QPaintEvent,
    QPen,
    QPixmap,
    QPolygonF,
    QResizeEvent,
)
from PySide6.QtWidgets import QSizePolicy, QWidget

from app.panels.plot_axes import plot_font
from app.panels.widgets import plot_colors

__all__ = ["PHASE_A_COLOR", "PHASE_B_COLOR", "SlicePreview", "VoxelPreview"]

#: Colours of the soft matrix (phase a, voxels 0) and the stiff phase b (voxels 1).
PHASE_A_COLOR = QColor("#dfe7f0")
PHASE_B_COLOR = QColor("#e8873a")

_COS30 = float(np.cos(np.pi / 6))
_AXIS_COLORS = {"x": QColor("#d32f2f"), "y": QColor("#2e7d32"), "z": QColor("#1565c0")}


#: The direction the isometric view looks from (toward the viewer), and the light's.
_VIEW = np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)
_LIGHT = np.array([0.35, 0.55, 1.0]) / np.linalg.norm([0.35, 0.55, 1.0])
#: The six face directions of a voxel and the corners of each face (unit cube).
_NORMALS = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
_FACE_CORNERS = {
    (0, 1): ((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)),
    (0, -1): ((0, 0, 0), (0, 1, 0), (0, 1, 1), (0, 0, 1)),
    (1, 1): ((0, 1, 0), (1, 1, 0), (1, 1, 1), (0, 1, 1)),
    (1, -1): ((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)),
    (2, 1): ((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)),
    (2, -1): ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)),
}


def _isometric(points: np.ndarray) -> np.ndarray:
    """(…, 3) points (x, y, z) → (…, 2) isometric screen offsets (right, down), seen from
    the (+x, +y, +z) corner with z up."""
    x, y, z = points[..., 0], points[..., 1], points[..., 2]
    return np.stack([(y - x) * _COS30, (x + y) * 0.5 - z], axis=-1)


class VoxelPreview(QWidget):
    """Isometric drawing of phase b of an (n, n, n) 0/1 cell (axis order x, y, z), turned by
    :meth:`set_rotation` (the rotation the panel applies to the material: the drawing shows
    the pattern as the rotated material has it), inside the cell's box and axes."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self._phases = np.zeros((2, 2, 2), dtype=np.int8)
        self._rotation = np.eye(3)
        self._pixmap: QPixmap | None = None
        self.setMinimumSize(170, 170)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)
        self.setToolTip(
            "Periodic cell: stiff phase b (orange) inside the soft matrix (box), turned as the "
            "result is rotated"
        )

    def sizeHint(self) -> QSize:
        return QSize(200, 190)

    @property
    def phases(self) -> np.ndarray:
        """The cell shown (read-only view)."""
        view = self._phases.view()
        view.setflags(write=False)
        return view

    @property
    def rotation(self) -> np.ndarray:
        """(3, 3) the rotation the cell is drawn with (a copy)."""
        return self._rotation.copy()

    def set_phases(self, phases: np.ndarray) -> None:
        """Show the (n, n, n) 0/1 cell ``phases``."""
        self._phases = np.asarray(phases, dtype=np.int8).copy()
        self._pixmap = None
        self.update()

    def set_rotation(self, rotation: np.ndarray) -> None:
        """Draw the cell turned by the proper rotation ``rotation`` (3, 3)."""
        self._rotation = np.array(rotation, dtype=np.float64).reshape(3, 3)
        self._pixmap = None
        self.update()

    def resizeEvent(self, event: QResizeEvent) -> None:
        self._pixmap = None
        super().resizeEvent(event)

    def changeEvent(self, event: QEvent) -> None:
        if event.type() == QEvent.Type.PaletteChange:  # a theme switch: redraw on new paper
            self._pixmap = None
        super().changeEvent(event)

    def paintEvent(self, event: QPaintEvent) -> None:
        if self._pixmap is None or self._pixmap.size() != self.size() * self.devicePixelRatioF():
            self._pixmap = self._render()
        painter = QPainter(self)
        painter.drawPixmap(0, 0, self._pixmap)
        painter.end()

    def _render(self) -> QPixmap:
        ratio = self.devicePixelRatioF()
        pixmap = QPixmap(self.size() * ratio)
        pixmap.setDevicePixelRatio(ratio)
        pixmap.fill(plot_colors().background)
        painter = QPainter(pixmap)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing)
        n = self._phases.shape[0]
        width, height = self.width(), self.height()
        box = np.array([(x, y, z) for x in (0, n) for y in (0, n) for z in (0, n)], float)
        extent = np.ptp(_isometric((box - n / 2) @ self._rotation.T), axis=0)
        scale = min((width - 30) / extent[0], (height - 30) / extent[1])
        centre = np.array([width / 2.0, height / 2.0])

        def screen(points: np.ndarray) -> np.ndarray:
            """Screen points (…, 2) of cell points (…, 3), turned, cube centred."""
            turned = (np.asarray(points, float) - n / 2) @ self._rotation.T
            return centre + scale * _isometric(turned)

        self._draw_box(painter, screen, n, hidden=True)
        self._draw_voxels(painter, screen)
        self._draw_box(painter, screen, n, hidden=False)
        self._draw_axes(painter, screen, n)
        painter.end()
        return pixmap

    def _draw_voxels(self, painter: QPainter, screen) -> None:
        """The faces of phase b that border phase a (or the cell's side) and face the
        viewer, far ones first, shaded by how they face the light."""
        ph = self._phases.astype(bool)
        n = ph.shape[0]
        padded = np.pad(ph, 1)
        edge = QPen(QColor(120, 60, 20, 70), 0.5)
        faces = []  # (depth, corners (4, 3), shade)
        for normal in _NORMALS:
            turned = self._rotation @ normal
            if turned @ _VIEW <= 1e-9:
                continue  # faces away from the viewer
            axis, sign = int(np.flatnonzero(normal)[0]), int(normal.sum())
            shifted = padded[
                1 + normal[0] : n + 1 + normal[0],
                1 + normal[1] : n + 1 + normal[1],
                1 + normal[2] : n + 1 + normal[2],
            ]
            cells = np.argwhere(ph & ~shifted)
            if not len(cells):
                continue
            corners = cells[:, None, :] + np.array(_FACE_CORNERS[(axis, sign)])[None]
            depth = ((corners.mean(axis=1) - n / 2) @ self._rotation.T) @ _VIEW
            shade = 0.55 + 0.45 * max(float(turned @ _LIGHT), 0.0)
            faces += [(d, c, shade) for d, c in zip(depth, corners, strict=True)]
        faces.sort(key=lambda face: face[0])
        painter.setPen(edge)
        for _depth, corners, shade in faces:
            color = QColor(PHASE_B_COLOR)
            color.setHsvF(color.hsvHueF(), color.hsvSaturationF(), min(1.0, shade + 0.05))
            painter.setBrush(color)
            painter.drawPolygon(QPolygonF([QPointF(*p) for p in screen(corners)]))

    @staticmethod
    def _box_edges(n: int) -> list[tuple[tuple[int, int, int], tuple[int, int, int]]]:
        corners = [(x, y, z) for x in (0, n) for y in (0, n) for z in (0, n)]
        return [
            (a, b)
            for a in corners
            for b in corners
            if a < b and sum(int(p != q) for p, q in zip(a, b, strict=True)) == 1
        ]

    def _edge_hidden(self, a: tuple[int, int, int], b: tuple[int, int, int], n: int) -> bool:
        """Whether a box edge lies behind the cell: both box faces along it face away."""
        facing = []
        for axis in range(3):
            if a[axis] == b[axis]:  # the edge lies on the box face of this axis at a[axis]
                normal = np.zeros(3)
                normal[axis] = 1.0 if a[axis] == n else -1.0
                facing.append((self._rotation @ normal) @ _VIEW > 1e-9)
        return not any(facing)

    def _draw_box(self, painter: QPainter, screen, n: int, hidden: bool) -> None:
        """Cell wireframe: the edges behind the cell dashed, under the voxels; the others
        solid, on top."""
        painter.setBrush(Qt.BrushStyle.NoBrush)
        for a, b in self._box_edges(n):
            if self._edge_hidden(a, b, n) != hidden:
                continue
            pen = QPen(QColor("#7a8ca0"), 1.0)
            if hidden:
                pen.setStyle(Qt.PenStyle.DashLine)
            painter.setPen(pen)
            (x0, y0), (x1, y1) = screen(np.array([a, b], float))
            painter.drawLine(QPointF(x0, y0), QPointF(x1, y1))

    def _draw_axes(self, painter: QPainter, screen, n: int) -> None:
        font = QFont(painter.font())
        font.setBold(True)
        painter.setFont(font)
        for axis, (name, color) in enumerate(_AXIS_COLORS.items()):
            start = np.zeros(3)
            start[axis] = n
            end = start.copy()
            end[axis] = 1.2 * n
            (x0, y0), (x1, y1) = screen(np.array([start, end]))
            painter.setPen(QPen(color, 1.4))
            painter.drawLine(QPointF(x0, y0), QPointF(x1, y1))
            painter.drawText(QRectF(x1 - 8, y1 - 9, 16, 16), Qt.AlignmentFlag.AlignCenter, name)


class SlicePreview(QWidget):
    """Three orthogonal slices of a 0/1 cell at a common depth ``index``: the xy plane at
    z = index, the xz plane at y = index and the yz plane at x = index, side by side or
    (``vertical``) stacked."""

    PLANES = (("xy", 2), ("xz", 1), ("yz", 0))

    def __init__(self, vertical: bool = False, parent: QWidget | None = None):
        super().__init__(parent)
        self._phases = np.zeros((2, 2, 2), dtype=np.int8)
        self._index = 0
        self._vertical = vertical
        self.setMinimumSize(*((90, 150) if vertical else (150, 70)))
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)

    def sizeHint(self) -> QSize:
        return QSize(120, 170) if self._vertical else QSize(300, 96)

    @property
    def index(self) -> int:
        """Depth of the slices (voxel index)."""
        return self._index

    def set_phases(self, phases: np.ndarray) -> None:
        """Show slices of the (n, n, n) 0/1 cell ``phases``."""
        self._phases = np.asarray(phases, dtype=np.int8).copy()
        self._index = min(self._index, self._phases.shape[0] - 1)
        self.update()

    def set_index(self, index: int) -> None:
        """Show the slices at depth ``index`` (clamped to the grid)."""
        self._index = int(np.clip(index, 0, self._phases.shape[0] - 1))
        self.update()

    def slice_image(self, plane: str) -> np.ndarray:
        """The (n, n) 0/1 slice ``"xy"``, ``"xz"`` or ``"yz"`` at the current depth, rows
        along the first letter's axis."""
        axis = dict(self.PLANES)[plane]
        return np.take(self._phases, self._index, axis=axis)

    def _slot_rects(self) -> list[tuple[QRectF, QRectF]]:
        """(label rect, image rect) of the three slices."""
        gap = 6
        if self._vertical:
            label_width = 58
            side = min((self.height() - 2 * gap - 2) / 3.0, self.width() - label_width - 4)
            top = (self.height() - (3 * side + 2 * gap)) / 2.0
            left = (self.width() - side - label_width) / 2.0
            return [
                (
                    QRectF(left + side + 4, top + i * (side + gap), label_width - 4, side),
                    QRectF(left, top + i * (side + gap), side, side),
                )
                for i in range(3)
            ]
        label_height = 16
        side = min((self.width() - 2 * gap - 2) / 3.0, self.height() - label_height - 2)
        left = (self.width() - (3 * side + 2 * gap)) / 2.0
        return [
            (
                QRectF(left + i * (side + gap), 0, side, label_height),
                QRectF(left + i * (side + gap), label_height, side, side),
            )
            for i in range(3)
        ]

    def paintEvent(self, event: QPaintEvent) -> None:
        painter = QPainter(self)
        painter.fillRect(self.rect(), plot_colors().background)
        a, b = PHASE_A_COLOR.rgb(), PHASE_B_COLOR.rgb()
        painter.setFont(plot_font(painter.font()))
        for (plane, axis), (label_rect, rect) in zip(self.PLANES, self._slot_rects(), strict=True):
            cells = self.slice_image(plane)
            n = cells.shape[0]
            # Image rows go down the screen: the second axis up, the first to the right.
            grid = np.ascontiguousarray(np.flipud(cells.T))
            rgb = np.where(grid == 1, b, a).astype(np.uint32)
            image = QImage(rgb.data, n, n, 4 * n, QImage.Format.Format_RGB32).copy()
            painter.drawImage(rect, image)
            painter.setPen(QPen(QColor("#7a8ca0"), 1.0))
            painter.drawRect(rect)
            painter.setPen(plot_colors().text)
            align = Qt.AlignmentFlag.AlignVCenter | (
                Qt.AlignmentFlag.AlignLeft if self._vertical else Qt.AlignmentFlag.AlignHCenter
            )
            depth = "xyz"[axis]
            sep = "\n" if self._vertical else "  "
            painter.drawText(label_rect, align, f"{plane}{sep}{depth} = {self._index}")
        painter.end()
