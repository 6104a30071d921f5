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
# Face shades of phase b: top (+z), right (+y), left (+x).
_FACE_COLORS = (QColor("#f6a860"), QColor("#c8691f"), QColor("#e08535"))
_AXIS_COLORS = {"x": QColor("#d32f2f"), "y": QColor("#2e7d32"), "z": QColor("#1565c0")}


class VoxelPreview(QWidget):
    """Isometric drawing of phase b of an (n, n, n) 0/1 cell (axis order x, y, z)."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self._phases = np.zeros((2, 2, 2), dtype=np.int8)
        self._pixmap: QPixmap | None = None
        self.setMinimumSize(170, 170)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)
        self.setToolTip("Periodic cell: stiff phase b (orange) inside the soft matrix (box)")

    def sizeHint(self) -> QSize:
        return QSize(200, 190)

    @property
    def phases(self) -> np.ndarray:
        """The cell shown (read-only view)."""
        view = self._phases.view()
        view.setflags(write=False)
        return view

    def set_phases(self, phases: np.ndarray) -> None:
        """Show the (n, n, n) 0/1 cell ``phases``."""
        self._phases = np.asarray(phases, dtype=np.int8).copy()
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
        # Projected extent of the cube: width 2 n cos30, height 2 n; margins for the axes.
        scale = min((width - 30) / (2 * n * _COS30), (height - 30) / (2.0 * n))
        cx, cy = width / 2.0, height / 2.0
        half = n / 2.0

        def corner(x: float, y: float, z: float) -> QPointF:
            """Screen point of cell point (x, y, z), cube centred in the widget."""
            x, y, z = x - half, y - half, z - half
            return QPointF(cx + (y - x) * _COS30 * scale, cy + ((x + y) * 0.5 - z) * scale)

        self._draw_box(painter, corner, n, hidden=True)
        self._draw_voxels(painter, corner)
        self._draw_box(painter, corner, n, hidden=False)
        self._draw_axes(painter, corner, n)
        painter.end()
        return pixmap

    def _draw_voxels(self, painter: QPainter, corner) -> None:
        ph = self._phases.astype(bool)
        n = ph.shape[0]
        # Visible faces from the (+x, +y, +z) corner: a face shows when the next voxel along
        # its normal is phase a or outside the cell.
        exposed = []
        for axis in range(3):
            nxt = np.zeros_like(ph)
            index = [slice(None)] * 3
            index[axis] = slice(0, n - 1)
            src = [slice(None)] * 3
            src[axis] = slice(1, n)
            nxt[tuple(index)] = ph[tuple(src)]
            exposed.append(ph & ~nxt)
        faces = []
        for axis in range(3):
            for i, j, k in np.argwhere(exposed[axis]):
                faces.append((i + j + k, axis, i, j, k))
        faces.sort()
        offsets = {
            0: ((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)),  # +x face
            1: ((0, 1, 0), (1, 1, 0), (1, 1, 1), (0, 1, 1)),  # +y face
            2: ((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)),  # +z face
        }
        colors = {0: _FACE_COLORS[2], 1: _FACE_COLORS[1], 2: _FACE_COLORS[0]}
        edge = QPen(QColor(120, 60, 20, 70), 0.5)
        for _, axis, i, j, k in faces:
            painter.setBrush(colors[axis])
            painter.setPen(edge)
            painter.drawPolygon(
                QPolygonF([corner(i + a, j + b, k + c) for a, b, c in offsets[axis]])
            )

    @staticmethod
    def _box_edges(n: int) -> list[tuple[tuple[int, int, int], tuple[int, int, int]]]:
        corners = [(x, y, z) for x in (0, n) for y in (0, n) for z in (0, n)]
        return [
            (a, b)
            for a in corners
            for b in corners
            if a < b and sum(int(p != q) for p, q in zip(a, b, strict=True)) == 1
        ]

    def _draw_box(self, painter: QPainter, corner, n: int, hidden: bool) -> None:
        """Cell wireframe: the three edges at the hidden (0, 0, 0) corner dashed, behind the
        voxels; the others solid, on top."""
        painter.setBrush(Qt.BrushStyle.NoBrush)
        for a, b in self._box_edges(n):
            at_back = a == (0, 0, 0)
            if at_back != hidden:
                continue
            pen = QPen(QColor("#7a8ca0"), 1.0)
            if hidden:
                pen.setStyle(Qt.PenStyle.DashLine)
            painter.setPen(pen)
            painter.drawLine(corner(*a), corner(*b))
        if hidden:
            painter.setPen(Qt.PenStyle.NoPen)
            faded = QColor(PHASE_A_COLOR)
            faded.setAlpha(110)
            painter.setBrush(faded)
            top = [(0, 0, n), (n, 0, n), (n, n, n), (0, n, n)]
            painter.drawPolygon(QPolygonF([corner(*p) for p in top]))

    def _draw_axes(self, painter: QPainter, corner, n: int) -> None:
        font = QFont(painter.font())
        font.setBold(True)
        painter.setFont(font)
        ends = {"x": (n + 0.22 * n, 0, 0), "y": (0, n + 0.22 * n, 0), "z": (0, 0, n + 0.18 * n)}
        starts = {"x": (n, 0, 0), "y": (0, n, 0), "z": (0, 0, n)}
        for name, color in _AXIS_COLORS.items():
            painter.setPen(QPen(color, 1.4))
            start, end = corner(*starts[name]), corner(*ends[name])
            painter.drawLine(start, end)
            painter.drawText(
                QRectF(end.x() - 8, end.y() - 9, 16, 16), Qt.AlignmentFlag.AlignCenter, name
            )


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
