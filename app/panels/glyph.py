"""A QPainter glyph of a material's anisotropy: the directional Young's modulus surface.

The surface is r(d) = (E(d) / max E)^p over unit directions d, with E(d) from
:meth:`gogreen_core.Material.directional_young`. An isotropic material is a sphere; a stiff
direction bulges out. p is 1 (radius ∝ E) unless max/min E exceeds :data:`MAX_SHAPE_RATIO`;
then it is lowered so that the softest direction keeps 1/MAX_SHAPE_RATIO of the radius: a fibre
composite (max/min E of 40 or more) stays a readable spindle, not a needle, and the legend says
so. Faces are coloured from blue (softest direction) to orange (stiffest), linearly in E.

Why QPainter and not a second pyvistaqt ``QtInteractor``: the glyph must render identically
on a desktop, under ``xvfb-run`` and with ``QT_QPA_PLATFORM=offscreen`` (the test setting).
With the offscreen platform a ``QtInteractor`` cannot create its OpenGL context
("QOpenGLWidget is not supported on this platform"), so it would show nothing and could not be
tested; a second VTK render window next to the sculpting viewport also costs a GL context and
startup time for a 200-pixel picture. A few hundred depth-sorted shaded quads drawn by QPainter
cost a few milliseconds, work everywhere, and can be orbited by dragging.
"""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, QRectF, QSize, Qt
from PySide6.QtGui import QColor, QFont, QMouseEvent, QPainter, QPaintEvent, QPen, QPolygonF
from PySide6.QtWidgets import QSizePolicy, QWidget

from app.panels.plot_axes import plot_font
from app.panels.widgets import plot_colors
from gogreen_core.physics.material import Material
from gogreen_core.physics.material_words import young_extremes

__all__ = ["YoungModulusGlyph"]

_SOFT = np.array([74.0, 127.0, 208.0])  # colour of the softest direction
_STIFF = np.array([236.0, 136.0, 58.0])  # colour of the stiffest direction
#: Largest max/min radius of the glyph's shape (see the module docstring).
MAX_SHAPE_RATIO = 4.0
_AXIS_COLORS = {"x": QColor("#d32f2f"), "y": QColor("#2e7d32"), "z": QColor("#1565c0")}


def _sphere_grid(n_lat: int, n_lon: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit directions on a latitude-longitude grid (n_lat+1, n_lon, 3) and the quads as
    index quadruples into the flattened grid (n_quads, 4)."""
    theta = np.linspace(0.0, np.pi, n_lat + 1)
    phi = np.linspace(0.0, 2.0 * np.pi, n_lon, endpoint=False)
    st, ct = np.sin(theta)[:, None], np.cos(theta)[:, None]
    dirs = np.stack(
        [
            st * np.cos(phi)[None, :],
            st * np.sin(phi)[None, :],
            np.broadcast_to(ct, (n_lat + 1, n_lon)),
        ],
        axis=-1,
    )
    rows, cols = np.meshgrid(np.arange(n_lat), np.arange(n_lon), indexing="ij")
    nxt = (cols + 1) % n_lon
    quads = np.stack(
        [
            rows * n_lon + cols,
            rows * n_lon + nxt,
            (rows + 1) * n_lon + nxt,
            (rows + 1) * n_lon + cols,
        ],
        axis=-1,
    ).reshape(-1, 4)
    return dirs.reshape(-1, 3), quads


class YoungModulusGlyph(QWidget):
    """Shaded 3D glyph of E(d) / max E; drag with the left button to orbit.

    Observable state (for tests and tooltips): :attr:`radii` (E at the grid directions),
    :attr:`young_range` and :attr:`revision` (bumped by every :meth:`set_material`).
    """

    def __init__(self, material: Material | None = None, parent: QWidget | None = None):
        super().__init__(parent)
        self._dirs, self._quads = _sphere_grid(18, 36)
        self._radii = np.ones(len(self._dirs))
        self._range = (1.0, 1.0)
        self._revision = 0
        self._azimuth = np.radians(35.0)
        self._elevation = np.radians(22.0)
        self._drag_origin: QPointF | None = None
        self.setMinimumSize(160, 160)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)
        self.setToolTip(
            "Directional Young's modulus E(d), scaled by its maximum (a strong anisotropy's "
            "shape compressed, see the legend). Drag to orbit."
        )
        if material is not None:
            self.set_material(material)

    # -- model -------------------------------------------------------------------------------
    def set_material(self, material: Material) -> None:
        """Show ``material``'s directional Young's modulus."""
        self._radii = np.asarray(material.directional_young(self._dirs), dtype=np.float64)
        e_min, e_max, _, _ = young_extremes(material)
        self._range = (e_min, e_max)
        self._revision += 1
        self.update()

    @property
    def radii(self) -> np.ndarray:
        """E(d) at the glyph's grid directions (copy)."""
        return self._radii.copy()

    @property
    def young_range(self) -> tuple[float, float]:
        """(min E, max E) over all directions (:func:`young_extremes`: the words' figure too)."""
        return self._range

    @property
    def shape_exponent(self) -> float:
        """p of the drawn radius (E / max E)^p: 1, or less for a strong anisotropy."""
        e_min, e_max = self.young_range
        ratio = e_max / e_min if e_min > 0 else np.inf
        return 1.0 if ratio <= MAX_SHAPE_RATIO else float(np.log(MAX_SHAPE_RATIO) / np.log(ratio))

    @property
    def shape_radii(self) -> np.ndarray:
        """The drawn radius of each grid direction, 1 in the stiffest (see the module
        docstring)."""
        return (self._radii / self.young_range[1]) ** self.shape_exponent

    @property
    def revision(self) -> int:
        """Number of materials shown so far."""
        return self._revision

    def sizeHint(self) -> QSize:
        return QSize(260, 210)

    # -- interaction -------------------------------------------------------------------------
    def mousePressEvent(self, event: QMouseEvent) -> None:
        if event.button() == Qt.MouseButton.LeftButton:
            self._drag_origin = event.position()

    def mouseMoveEvent(self, event: QMouseEvent) -> None:
        if self._drag_origin is None:
            return
        delta = event.position() - self._drag_origin
        self._drag_origin = event.position()
        self._azimuth -= np.radians(delta.x() * 0.6)
        self._elevation = float(np.clip(self._elevation + np.radians(delta.y() * 0.6), -1.5, 1.5))
        self.update()

    def mouseReleaseEvent(self, event: QMouseEvent) -> None:
        self._drag_origin = None

    # -- drawing -----------------------------------------------------------------------------
    def _view_basis(self) -> np.ndarray:
        """Rows: screen right, screen up, towards the viewer (world z stays up)."""
        ca, sa = np.cos(self._azimuth), np.sin(self._azimuth)
        ce, se = np.cos(self._elevation), np.sin(self._elevation)
        toward = np.array([ce * ca, ce * sa, se])
        right = np.array([-sa, ca, 0.0])
        up = np.cross(toward, right)
        return np.stack([right, up, toward])

    def paintEvent(self, event: QPaintEvent) -> None:
        painter = QPainter(self)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing)
        colors = self._colors = plot_colors()
        painter.fillRect(self.rect(), colors.background)
        painter.setPen(QPen(colors.frame))
        painter.drawRect(self.rect().adjusted(0, 0, -1, -1))
        legend_height = 34
        size = min(self.width(), self.height() - legend_height)
        centre = QPointF(self.width() / 2.0, (self.height() - legend_height) / 2.0 + 2)
        scale = 0.40 * size

        e_min, e_max = self.young_range
        points = self._dirs * self.shape_radii[:, None]
        view = points @ self._view_basis().T  # (N, 3): right, up, depth
        quads = view[self._quads]  # (Q, 4, 3)
        depth = quads[:, :, 2].mean(axis=1)
        normals = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
        lengths = np.linalg.norm(normals, axis=1)
        light = np.array([-0.35, 0.55, 0.76])
        shade = np.abs(normals @ light) / np.where(lengths > 0, lengths, 1.0)
        isotropic = e_max - e_min <= 1e-9 * e_max
        stiffness = (
            np.zeros(len(self._quads))  # one colour: the soft end
            if isotropic
            else (self._radii[self._quads].mean(axis=1) - e_min) / (e_max - e_min)
        )
        base = _SOFT[None, :] + stiffness[:, None] * (_STIFF - _SOFT)[None, :]
        rgb = np.clip(base * (0.35 + 0.65 * shade[:, None]) + 18.0 * shade[:, None] ** 8, 0, 255)

        def screen(p: np.ndarray) -> QPointF:
            return QPointF(centre.x() + scale * p[0], centre.y() - scale * p[1])

        self._draw_axes(painter, screen, behind=True)
        painter.setPen(Qt.PenStyle.NoPen)
        for q in np.argsort(depth):
            if lengths[q] == 0:
                continue
            color = QColor(int(rgb[q, 0]), int(rgb[q, 1]), int(rgb[q, 2]))
            painter.setBrush(color)
            painter.setPen(QPen(color, 0.6))
            painter.drawPolygon(QPolygonF([screen(p) for p in quads[q]]))
        self._draw_axes(painter, screen, behind=False)
        self._draw_legend(painter, e_min, e_max, legend_height)
        painter.end()

    def _draw_axes(self, painter: QPainter, screen, behind: bool) -> None:
        """Material-frame axes x, y, z (world axes; the glyph rotates with the material)."""
        basis = self._view_basis()
        font = QFont(painter.font())
        font.setBold(True)
        painter.setFont(font)
        for index, (name, color) in enumerate(_AXIS_COLORS.items()):
            axis = np.zeros(3)
            axis[index] = 1.0
            tip = basis @ (1.18 * axis)
            if (tip[2] < 0) != behind:
                continue
            pen = QPen(color, 1.4)
            if behind:
                pen.setStyle(Qt.PenStyle.DashLine)
            painter.setPen(pen)
            painter.drawLine(screen(np.zeros(3)), screen(tip))
            label = screen(basis @ (1.30 * axis))
            painter.drawText(
                QRectF(label.x() - 8, label.y() - 8, 16, 16), Qt.AlignmentFlag.AlignCenter, name
            )

    def _draw_legend(self, painter: QPainter, e_min: float, e_max: float, height: int) -> None:
        top = self.height() - height
        bar = QRectF(10, top + 4, 80, 9)
        for i in range(40):
            t = i / 39.0
            c = _SOFT + t * (_STIFF - _SOFT)
            painter.fillRect(
                QRectF(
                    bar.x() + i * bar.width() / 40, bar.y(), bar.width() / 40 + 0.5, bar.height()
                ),
                QColor(int(c[0]), int(c[1]), int(c[2])),
            )
        painter.setPen(self._colors.text)
        font = plot_font(painter.font())
        font.setBold(False)
        painter.setFont(font)
        if e_max - e_min <= 1e-9 * e_max:
            text = f"E = {e_max:.4g} in every direction"
        else:
            text = f"E  {e_min:.3g} … {e_max:.3g}   (max/min {e_max / e_min:.3g})"
        painter.drawText(
            QRectF(96, top, self.width() - 100, 18), Qt.AlignmentFlag.AlignVCenter, text
        )
        painter.setPen(self._colors.muted)
        painter.drawText(
            QRectF(10, top + 16, self.width() - 20, 16),
            Qt.AlignmentFlag.AlignVCenter,
            (
                f"soft → stiff · shape ∝ E^{self.shape_exponent:.2f} · drag to orbit"
                if self.shape_exponent < 1.0
                else "soft → stiff direction · drag to orbit"
            ),
        )
