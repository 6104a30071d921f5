"""The Mesh menu: subdivide, remesh, dynamic topology and its detail size, invert and clear the
mask; and the view kept in step with them.

A subdivision of a big mesh and every remesh run off the GUI thread
(:func:`prepare_subdivision`, :meth:`Remesher.prepare` on copies of the mesh, with progress in
the status bar; a remesh can be cancelled); the window refuses strokes, undo and mask edits
meanwhile, and the result is adopted on the GUI thread (``prepared``: one undo step, one
session record). Whenever the sculptor's face array or mask
changed (a subdivision, its undo, a mask stroke), :meth:`MeshEdits.sync` redraws the mesh
(a new surface index for picking and normals, the pins, the mask's tint).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from PySide6.QtCore import QObject, Qt, QTimer
from PySide6.QtGui import QGuiApplication
from PySide6.QtWidgets import QInputDialog, QMenu, QMenuBar

from app.background import BackgroundRunner, Task
from app.level_of_detail import edit_renumbering
from gogreen_core.mesh.mesh_state import MeshEdit
from gogreen_core.mesh.subdivision import PreparedSubdivision, prepare_subdivision
from gogreen_core.sculpt.stroke import PreparedRemesh

if TYPE_CHECKING:
    from app.main_window import MainWindow
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = ["BACKGROUND_SUBDIVISION_FACES", "MeshEdits"]

#: Meshes with at least this many faces are subdivided off the GUI thread: the 124k-face ogre
#: took 0.26-0.37 s here (a loaded machine), the 2M-face one 2.3 s.
BACKGROUND_SUBDIVISION_FACES = 50_000
_WORKING = {"subdivide": "subdividing", "remesh": "remeshing"}
_DONE_TO = {"subdivide": "subdivided", "remesh": "remeshed"}


class MeshEdits(QObject):
    """The Mesh menu of ``window`` and what keeps its viewport in step with the mesh."""

    def __init__(self, window: MainWindow) -> None:
        super().__init__(window)
        self.window = window
        self._runner = BackgroundRunner(self)
        self._runner.progress.connect(self._progress)
        self._runner.finished.connect(self._prepared)
        self._runner.failed.connect(self._failed)
        self._runner.cancelled.connect(lambda _job: self._end_job())
        self._job: int | None = None
        self._job_kind = "subdivide"  # what the running job does ("subdivide" or "remesh")
        self._job_started = 0.0
        self._progress_bar = None
        self._shown_faces: np.ndarray | None = None
        #: Seconds of the last subdivision, from the request to the mesh shown (benchmarks).
        self.last_seconds = 0.0

    def build_menu(self, bar: QMenuBar) -> QMenu:
        """The Mesh menu: Subdivide (Ctrl+D), Subdivide Unmasked, Invert and Clear Mask."""
        menu = bar.addMenu("Me&sh")  # not Alt+M: Blender's Clear Mask
        action = self.window._action
        self.subdivide_action = action(menu, "&Subdivide", self.subdivide, "subdivide")
        self.subdivide_unmasked_action = action(
            menu,
            "Subdivide &Unmasked",
            lambda: self.subdivide(unmasked_only=True),
            "subdivide_unmasked",
        )
        menu.addSeparator()
        self.dynamic_topology_action = action(
            menu, "D&ynamic Topology", self.toggle_dynamic_topology, "dynamic_topology"
        )
        self.dynamic_topology_action.setCheckable(True)
        model = self.window.model
        model.events.dynamic_topology.connect(
            lambda event: self.dynamic_topology_action.setChecked(bool(event.value))
        )
        # the cursor's detail circle follows (once the engine has the new settings)
        for event in (model.events.dynamic_topology, model.events.detail_size):
            event.connect(lambda _event: QTimer.singleShot(0, self.window.viewport.refresh_cursor))
        action(menu, "Detail Si&ze…", self.ask_detail_size)
        self.remesh_action = action(menu, "&Remesh", self.remesh, "remesh")
        action(menu, "Remesh Un&masked", lambda: self.remesh(unmasked_only=True))
        menu.addSeparator()
        action(menu, "&Invert Mask", self.invert_mask, "mask_invert")
        action(menu, "&Clear Mask", self.clear_mask, "mask_clear")
        return menu

    # -- state -------------------------------------------------------------------------------
    @property
    def _sculptor(self) -> Sculptor:
        """The shown document's sculptor (the menu acts only while one is shown)."""
        sculptor = self.window.sculptor
        assert sculptor is not None
        return sculptor

    @property
    def busy(self) -> bool:
        """A subdivision or a remesh is being computed."""
        return self._job is not None

    def refusal(self) -> str | None:
        """Why the mesh may not change now (a subdivision runs), or None."""
        if self.busy:
            return (
                f"the mesh is being {_DONE_TO[self._job_kind]} (see the status bar); wait until "
                "it is done"
            )
        return None

    def attach(self) -> None:
        """A new document is shown: forget a running subdivision; the view shows its mesh."""
        if self._job is not None:
            self._runner.cancel(self._job)
            self._end_job()
        sculptor = self._sculptor
        self._shown_faces = sculptor.faces
        self.window.viewport.show_mask_of(sculptor)

    def cancel(self) -> None:
        """Drop a running subdivision or remesh (closing the window)."""
        self._runner.cancel()

    def wait(self, msecs: int = -1) -> bool:
        """Block until a running subdivision or remesh is computed and adopted (tests)."""
        return self._runner.wait(msecs)

    # -- view --------------------------------------------------------------------------------
    def sync(self, indices: np.ndarray | None = None, stepped: bool = False) -> bool:
        """Bring the view up to the sculptor's mesh: when its faces changed (a subdivision,
        its undo or redo) the whole mesh is shown again, with its pins and mask (True);
        else the vertices that differ (or ``indices``), pins and mask are drawn (False).
        ``stepped``: after an undo or redo (a dynamic-topology stroke's renumbers the index)."""
        document = self.window.document
        if document is None:
            return False
        sculptor = document.sculptor
        viewport = self.window.viewport
        remade = sculptor.faces is not self._shown_faces
        if remade:
            change = sculptor.remesher.mesh.renumbering  # a stroke's: local
            edit = sculptor.history.restored_state
            if stepped and isinstance(edit, MeshEdit) and self._shown_faces is not None:
                change = edit_renumbering(edit, self._shown_faces)  # its undo or redo: local
            self._shown_faces = sculptor.faces
            viewport.set_mesh(
                sculptor.vertices, sculptor.faces, reset_camera=False, renumbering=change
            )
            self.window.look.apply_mesh_look()
            self.window.surface_progress.setValue(0)
            self.window.surface_progress.setVisible(viewport.surface_building)
        viewport.show_sculptor(None if remade else indices)
        return remade

    # -- actions -----------------------------------------------------------------------------
    def _ready(self, what: str) -> bool:
        window = self.window
        if window.document is None:
            return False
        reason = self.refusal() or ("a stroke is in progress" if window.tools.dragging else None)
        if reason:
            window.flash(f"Cannot {what}: {reason}")
            return False
        return True

    def invert_mask(self) -> None:
        """Mesh → Invert Mask (Ctrl+I): one undo step."""
        if self._ready("invert the mask"):
            self._sculptor.mask.invert()
            self._edited("Mask inverted")

    def clear_mask(self) -> None:
        """Mesh → Clear Mask (Alt+M): one undo step (nothing when nothing is masked)."""
        if not self._ready("clear the mask"):
            return
        mask = self._sculptor.mask
        if not mask.any:
            self.window.flash("Nothing is masked")
            return
        mask.clear()
        self._edited("Mask cleared")

    def toggle_dynamic_topology(self, on: bool) -> None:
        """Mesh → Dynamic Topology: strokes remesh what they move (an undo step)."""
        self.window.model.dynamic_topology = bool(on)
        size = self.window.model.detail_size
        detail = "the surface's own edge length" if size is None else f"{100 * size:g} %"
        self.window.flash(f"Dynamic topology {'on' if on else 'off'} (detail: {detail})")

    def ask_detail_size(self) -> None:
        """Mesh → Detail Size: the target edge length of dynamic topology and
        Remesh, in percent of the model size; 0 keeps the edge length the surface had."""
        model = self.window.model
        current = 0.0 if model.detail_size is None else 100.0 * model.detail_size
        value, ok = QInputDialog.getDouble(
            self.window,
            "Detail size",
            "Edge length in % of the model size (0: the surface's own):",
            current,
            0.0,
            25.0,
            3,
        )
        if ok:
            model.detail_size = None if value < 0.01 else value / 100.0

    def remesh(self, unmasked_only: bool = False) -> None:
        """Mesh → Remesh (Ctrl+R) or Remesh Unmasked: edges of the detail size all over (without
        one, each vertex's own edge length: as many vertices, evened out), one undo step.
        Computed off the GUI thread on a copy of the mesh, with progress in the status bar;
        Ctrl+R again (or Remesh Unmasked) while it runs cancels it, the mesh untouched."""
        if self._job is not None and self._job_kind == "remesh":
            self._runner.cancel(self._job)
            self._end_job()
            self.window.flash("Remesh cancelled: the mesh is unchanged")
            return
        if not self._ready("remesh"):
            return
        sculptor = self._sculptor
        if unmasked_only and not sculptor.mask.any:
            self.window.flash("Nothing is masked: Remesh works on the whole mesh")
        size = self.window.model.detail_size
        try:
            prepared = sculptor.remesher.prepare(size, unmasked_only)
        except (ValueError, RuntimeError) as exc:
            self.window.show_error("Cannot remesh", str(exc))
            return
        self._job_started = time.perf_counter()
        self._start_job("remesh", lambda task: prepared.compute(task.progress))
        self.window.flash(
            f"Remeshing {len(sculptor.faces):,} faces to {_detail_words(size)}… "
            "(Ctrl+R again cancels)"
        )

    def _remeshed(self, prepared: PreparedRemesh) -> None:
        sculptor = self._sculptor
        op = prepared.op
        try:
            sculptor.remesher.remesh(
                op.detail_size, op.unmasked_only, op.iterations, prepared=prepared
            )
        except (ValueError, RuntimeError) as exc:
            self.window.show_error("Cannot remesh", str(exc))
            return
        self.last_seconds = time.perf_counter() - self._job_started
        self._edited(
            f"Remeshed to {_detail_words(op.detail_size)}: "
            f"{len(sculptor.vertices):,} vertices, {len(sculptor.faces):,} faces in "
            f"{self.last_seconds:.1f} s (Ctrl+Z undoes it)"
        )

    def subdivide(self, unmasked_only: bool = False) -> None:
        """Mesh → Subdivide (Ctrl+D) or Subdivide Unmasked: Loop subdivision, one undo step;
        off the GUI thread with progress for a mesh of :data:`BACKGROUND_SUBDIVISION_FACES`
        faces or more."""
        if not self._ready("subdivide"):
            return
        sculptor = self._sculptor
        if unmasked_only and not sculptor.mask.any:
            self.window.flash("Nothing is masked: Subdivide refines the whole mesh")
            return
        self._job_started = time.perf_counter()
        if len(sculptor.faces) < BACKGROUND_SUBDIVISION_FACES:
            sculptor.subdivide(unmasked_only)
            self._subdivided()
            return
        source = sculptor.mesh
        self._start_job(
            "subdivide", lambda task: prepare_subdivision(source, unmasked_only, task.progress)
        )
        self.window.flash(f"Subdividing {len(source.faces):,} faces…")

    def _start_job(self, kind: str, work: Callable[[Task], object]) -> None:
        """Run ``work`` off the GUI thread, its progress in the status bar; the mesh actions
        wait (except the remesh keys, which cancel a remesh)."""
        self._job_kind = kind
        self._job = self._runner.submit(work)
        bar = self._bar()
        bar.setFormat(f"{_WORKING[kind]} %p%")
        bar.setValue(0)
        bar.show()
        self._enable(False)

    def _bar(self):
        if self._progress_bar is None:
            self._progress_bar = self.window.status.add_progress(
                100, "subdividing %p%", "The mesh is being rebuilt; sculpting waits for it"
            )
        return self._progress_bar

    def _enable(self, on: bool) -> None:
        for action in (self.subdivide_action, self.subdivide_unmasked_action):
            action.setEnabled(on)

    def _progress(self, job: int, fraction: float) -> None:
        if job == self._job:
            self._bar().setValue(round(100 * fraction))

    def _prepared(self, job: int, prepared: PreparedSubdivision | PreparedRemesh) -> None:
        """The background job ended: say that the new mesh is being shown (adopting it and the
        first frame of a 4M-vertex mesh take seconds on the GUI thread here, measured 0.4 s
        and 3 s), let the message and a busy cursor paint, then adopt it."""
        if job != self._job or self.window.document is None:
            return
        self._bar().setFormat("showing the mesh…")
        self._bar().setValue(100)
        if isinstance(prepared, PreparedRemesh):
            self._end_job()
            self._remeshed(prepared)
            return
        vertices = len(prepared.result.vertices)
        self.window.flash(f"Showing the subdivided mesh ({vertices:,} vertices)…")
        QGuiApplication.setOverrideCursor(Qt.CursorShape.WaitCursor)
        QTimer.singleShot(50, lambda: self._adopt(job, prepared))

    def _adopt(self, job: int, prepared: PreparedSubdivision) -> None:
        try:
            if job != self._job or self.window.document is None:
                return  # another document was opened meanwhile
            self._end_job()
            sculptor = self._sculptor
            try:
                sculptor.subdivide(prepared.unmasked_only, prepared=prepared)
            except (ValueError, RuntimeError) as exc:
                self.window.show_error("Cannot subdivide", str(exc))
                return
            self._subdivided()
        finally:
            # after the first frame of the new mesh (the paint just requested)
            QTimer.singleShot(0, QGuiApplication.restoreOverrideCursor)

    def _failed(self, job: int, error: Exception) -> None:
        if job == self._job:
            title = f"Cannot {self._job_kind}"
            self._end_job()
            self.window.show_error(title, f"{type(error).__name__}: {error}")

    def _end_job(self) -> None:
        self._job = None
        if self._progress_bar is not None:
            self._progress_bar.hide()
        self._enable(True)

    def _subdivided(self) -> None:
        sculptor = self._sculptor
        self.last_seconds = time.perf_counter() - self._job_started
        self._edited(
            f"Subdivided: {len(sculptor.vertices):,} vertices, {len(sculptor.faces):,} faces "
            f"in {self.last_seconds:.1f} s (Ctrl+Z undoes it)"
        )

    def _edited(self, message: str) -> None:
        self.sync()
        self.window.refresh_title()
        self.window._refresh_status()
        self.window.flash(message)


def _detail_words(size: float | None) -> str:
    """A remesh's detail size in the status bar's words."""
    return (
        "the surface's own edge lengths"
        if size is None
        else f"{100 * size:.3g} % of the model size"
    )
