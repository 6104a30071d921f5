"""The sculpting engine: a mesh, a material, a falloff, brushes, constraints, history, a log.

Everything the app does with the mouse goes through :class:`Sculptor`, so a script (or
``gogreen replay``) can do it too. Data flows one way: material → kernel → brush → integrator →
new vertex positions.

How a stroke accumulates: a stroke is :meth:`Sculptor.begin_stroke`, one
:meth:`Sculptor.stroke_event` per mouse event, :meth:`Sculptor.end_stroke`. Each event moves the
current (already deformed) vertices along the brush's displacement field taken as a velocity
over pseudo-time [0, 1] (RK4, ``brush.substeps`` steps, paper Sec. 3.2); successive events
compose, so a stroke is the composition of the flows of its events. For grab brushes the load
center travels with the cursor during each event, so the point under the cursor follows the
cursor path exactly. A stroke is one undo step, and one entry of the session log.

Constraints (paper Fig. 1) are applied as a direct displacement u(x) = Σ_j G(x − p_j) f_j on
every vertex (no pseudo-time), so the constrained points land exactly on their targets.
"""

from __future__ import annotations

import contextlib
import hashlib
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from gogreen_core._expansion import near_segment
from gogreen_core.brushes import (
    AFFINE_BRUSHES,
    Brush,
    BrushEvent,
    affine_unit_load,
    default_wrinkle_weights,
    mirror_signs,
)
from gogreen_core.constraints import ConstraintSet
from gogreen_core.history import History
from gogreen_core.kernel import GreenKernel
from gogreen_core.material import Material
from gogreen_core.radial import GaussianRadial, MultiscaleRadial, RadialProfile, radial_from_dict

__all__ = ["SESSION_FORMAT", "Sculptor", "mesh_fingerprint"]

SESSION_FORMAT = "gogreen-session"
SESSION_VERSION = 1
#: Operations that set a value; consecutive ones collapse into the last in the session log.
_SETTING_OPS = frozenset({"material", "falloff", "constraint_radius"})
#: Relative step of the central differences that measure an affine brush's strength.
_JACOBIAN_STEP = 1e-3


def mesh_fingerprint(vertices: np.ndarray) -> str:
    """SHA-256 of the float64 vertex array: tells whether a session replays on its own mesh."""
    return hashlib.sha256(np.ascontiguousarray(vertices, dtype=np.float64).tobytes()).hexdigest()


def _check_mesh(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    v = np.array(vertices, dtype=np.float64)
    f = np.array(faces, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0:
        raise ValueError(f"vertices must be a non-empty (N, 3) array (got shape {v.shape})")
    if not np.all(np.isfinite(v)):
        raise ValueError("vertices contain NaN or infinite coordinates")
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"faces must be an (M, 3) array (got shape {f.shape})")
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        raise ValueError(f"faces reference vertices outside 0..{len(v) - 1}")
    return v, f


@dataclass
class _Stroke:
    brush: Brush
    before: np.ndarray
    touched: np.ndarray
    events: list = field(default_factory=list)


class Sculptor:
    """Sculpting state and operations (no GUI).

    Parameters
    ----------
    vertices : (N, 3) float64, faces : (M, 3) int64
        The mesh; vertices are copied and then edited in place (see :attr:`vertices`).
    material : Material, default isotropic E = 1, ν = 0.3
    l_max : int, default 8
    falloff : RadialProfile, default GaussianRadial
        The falloff shape; its ε is ignored (each brush sets ε = radius · model size).
    degree_weights : (l_max + 1,) floats, optional
        Per-degree weights of the wrinkle brush (default :func:`default_wrinkle_weights`).
    history_bytes : memory cap of the undo history.
    """

    def __init__(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        *,
        material: Material | None = None,
        l_max: int = 8,
        falloff: RadialProfile | None = None,
        degree_weights: np.ndarray | None = None,
        history_bytes: int = 512 * 2**20,
    ):
        self._vertices, self._faces = _check_mesh(vertices, faces)
        low, high = self._vertices.min(axis=0), self._vertices.max(axis=0)
        self.model_size = float(np.linalg.norm(high - low))
        if not self.model_size > 0:
            raise ValueError("the mesh has zero size (all vertices coincide)")
        #: Point of the mirror planes: the center of the bounding box at load.
        self.origin = 0.5 * (low + high)
        self.history = History(history_bytes)
        self._material = Material.isotropic(1.0, 0.3)
        self._l_max = 8
        self._falloff: RadialProfile = GaussianRadial(1.0)
        self._weights: np.ndarray | None = None
        self._kernels: dict[str, GreenKernel] = {}
        self._stroke: _Stroke | None = None
        self._constraints: ConstraintSet | None = None
        self._constraint_radius = 0.1
        self._operations: list[dict] = []
        self._fingerprint = mesh_fingerprint(self._vertices)
        self._set_falloff(falloff or GaussianRadial(1.0), l_max, degree_weights)
        if material is not None:
            self._set_material(material)
        self._initial = self._settings()

    # -- state -------------------------------------------------------------------------------
    @property
    def vertices(self) -> np.ndarray:
        """(N, 3) current positions (read-only view; the engine edits the array in place)."""
        view = self._vertices.view()
        view.setflags(write=False)
        return view

    @property
    def faces(self) -> np.ndarray:
        return self._faces

    @property
    def material(self) -> Material:
        return self._material

    @property
    def falloff(self) -> RadialProfile:
        return self._falloff

    @property
    def l_max(self) -> int:
        return self._l_max

    @property
    def degree_weights(self) -> np.ndarray:
        """Weights of the wrinkle brush (l_max + 1,)."""
        if self._weights is None:
            return default_wrinkle_weights(self._l_max)
        return self._weights

    @property
    def in_stroke(self) -> bool:
        return self._stroke is not None

    def _settings(self) -> dict:
        return {
            "material": self._material.to_dict(),
            "falloff": self._falloff.to_dict(),
            "l_max": self._l_max,
            "degree_weights": None if self._weights is None else self._weights.tolist(),
        }

    # -- settings ----------------------------------------------------------------------------
    def _set_material(self, material: Material) -> None:
        if not isinstance(material, Material):
            raise ValueError(f"material must be a Material (got {type(material).__name__})")
        self._material = material
        self._kernels.clear()
        self._rebuild_constraints()

    def set_material(self, material: Material) -> None:
        """Use ``material`` for the next operations."""
        self._refuse_in_stroke("change the material")
        self._set_material(material)
        self._log({"op": "material", "material": material.to_dict()})

    def _set_falloff(
        self, falloff: RadialProfile, l_max: int | None, degree_weights: np.ndarray | None
    ) -> None:
        if not isinstance(falloff, RadialProfile) or isinstance(falloff, MultiscaleRadial):
            raise ValueError("falloff must be a single RadialProfile (Gaussian, Kelvinlet, spline)")
        l_max = self._l_max if l_max is None else l_max
        shape = falloff.with_eps(1.0)  # a copy: later edits of the caller's need another call
        current = self._kernels.get("full")
        if current is not None and current.l_max == l_max:
            full = current.with_radial(shape)  # same material: no new quadrature
        else:
            full = GreenKernel(self._material, l_max, shape)  # validates l_max and the falloff
        weights = None if degree_weights is None else np.array(degree_weights, dtype=np.float64)
        if weights is not None and (
            weights.shape != (l_max + 1,) or not np.isfinite(weights).all()
        ):
            raise ValueError(f"degree_weights must be l_max + 1 = {l_max + 1} finite numbers")
        self._falloff, self._l_max, self._weights = shape, int(l_max), weights
        self._kernels = {"full": full}
        self._rebuild_constraints()

    def set_falloff(
        self,
        falloff: RadialProfile,
        l_max: int | None = None,
        degree_weights: np.ndarray | None = None,
    ) -> None:
        """Use this falloff shape (and truncation degree, wrinkle weights) from now on."""
        self._refuse_in_stroke("change the falloff")
        self._set_falloff(falloff, l_max, degree_weights)
        settings = self._settings()
        self._log(
            {"op": "falloff", **{k: settings[k] for k in ("falloff", "l_max", "degree_weights")}}
        )

    def _refuse_in_stroke(self, what: str) -> None:
        if self._stroke is not None:
            raise RuntimeError(f"cannot {what} during a stroke; end the stroke first")

    def _base_kernel(self, wrinkle: bool) -> GreenKernel:
        key = "wrinkle" if wrinkle else "full"
        if key not in self._kernels:
            weights = self.degree_weights if wrinkle else None
            self._kernels[key] = GreenKernel(self._material, self._l_max, self._falloff, weights)
        return self._kernels[key]

    def kernel(self, brush: Brush) -> GreenKernel:
        """The kernel of ``brush`` on this model: its falloff, ε and degree weights."""
        radial = self._falloff.with_eps(brush.eps(self.model_size))
        if brush.kind == "grab_biscale":
            radial = MultiscaleRadial.biscale(radial)
        elif brush.kind == "grab_triscale":
            radial = MultiscaleRadial.triscale(radial)
        return self._base_kernel(brush.kind == "wrinkle").with_radial(radial)

    # -- strokes -----------------------------------------------------------------------------
    def begin_stroke(self, brush: Brush) -> None:
        """Start a stroke with ``brush``; events follow, then :meth:`end_stroke`."""
        self._refuse_in_stroke("begin a stroke")
        if not isinstance(brush, Brush):
            raise ValueError(f"brush must be a Brush (got {type(brush).__name__})")
        self._stroke = _Stroke(
            brush, self._vertices.copy(), np.zeros(len(self._vertices), dtype=bool)
        )

    def stroke_event(self, event: BrushEvent) -> np.ndarray:
        """Apply one mouse event of the current stroke; returns the indices of moved vertices."""
        if self._stroke is None:
            raise RuntimeError("stroke_event outside a stroke: call begin_stroke first")
        if not isinstance(event, BrushEvent):
            raise ValueError(f"a stroke event must be a BrushEvent (got {type(event).__name__})")
        moved = self._apply_event(self._stroke.brush, event)
        self._stroke.touched[moved] = True
        self._stroke.events.append(event)
        return moved

    def end_stroke(self) -> np.ndarray:
        """Finish the stroke: one undo step and one log entry. Returns the moved indices."""
        stroke, self._stroke = self._stroke, None
        if stroke is None:
            return np.zeros(0, dtype=np.int64)
        idx = np.flatnonzero(stroke.touched)
        changed = np.any(stroke.before[idx] != self._vertices[idx], axis=1)
        idx = idx[changed]
        if len(idx):
            self.history.record(
                f"{stroke.brush.kind} stroke", idx, stroke.before[idx], self._vertices[idx]
            )
        if stroke.events:
            self._log(
                {
                    "op": "stroke",
                    "brush": stroke.brush.to_dict(),
                    "events": [e.to_dict() for e in stroke.events],
                }
            )
        return idx

    def cancel_stroke(self) -> None:
        """Abandon the current stroke, restoring the vertices as they were before it."""
        if self._stroke is not None:
            self._vertices[:] = self._stroke.before
            self._stroke = None

    def apply_brush(self, brush: Brush, events: list[BrushEvent]) -> np.ndarray:
        """A whole stroke at once; returns the moved indices."""
        self.begin_stroke(brush)
        try:
            for event in events:
                self.stroke_event(event)
        except Exception:
            self.cancel_stroke()
            raise
        return self.end_stroke()

    def _load(self, brush: Brush, kernel: GreenKernel, event: BrushEvent):
        """(load, center_step) of one event: a force (3,) or an affine load (3, 3)."""
        if brush.kind in AFFINE_BRUSHES:
            unit = affine_unit_load(brush.kind, event.axis, event.direction)
            # Deformation gradient at the center per unit load, by central differences.
            h = _JACOBIAN_STEP * kernel.eps
            probes = event.center + h * np.vstack([np.eye(3), -np.eye(3)])
            u = kernel.affine_displacement(probes, event.center, unit)
            jacobian = ((u[:3] - u[3:]) / (2 * h)).T  # [i, p] = ∂u_i/∂x_p
            # Its component along the unit load (the sign depends on the material: Kelvinlets'
            # scale load contracts for ν < 1/2), normalized away so `amount` means the same.
            response = float(np.sum(jacobian * unit))
            if not abs(response) > 1e-3 * np.linalg.norm(jacobian):
                raise ValueError(
                    f"the {brush.kind} brush has no effect with this material and falloff "
                    f"(response {response:.3g})"
                )
            return unit * (brush.strength * event.amount / response), np.zeros(3)
        delta = brush.strength * event.delta
        # The wrinkle brush's force comes from the full (unweighted) kernel at the same falloff.
        full = (
            self._base_kernel(False).with_radial(kernel.radial)
            if brush.kind == "wrinkle"
            else kernel
        )
        g0 = full.green(np.zeros((1, 3)))[0]
        return np.linalg.solve(g0, delta), delta

    def _active(self, brush: Brush, center: np.ndarray, step: np.ndarray) -> np.ndarray:
        """Indices of vertices the brush can reach during the event (inside the influence
        ball around the segment the center travels, or its mirror images)."""
        cutoff = brush.cutoff(self.model_size)
        if cutoff is None:
            return np.arange(len(self._vertices))
        reach = np.empty(len(self._vertices), dtype=bool)
        signs = mirror_signs(brush.symmetry)
        near_segment(self._vertices, center, step, cutoff[1], signs, self.origin, reach)
        return np.flatnonzero(reach)

    def _apply_event(self, brush: Brush, event: BrushEvent) -> np.ndarray:
        kernel = self.kernel(brush)
        load, step = self._load(brush, kernel, event)
        active = self._active(brush, event.center, step)
        if len(active):
            self._vertices[active] = kernel.streamlines(
                self._vertices[active],
                event.center,
                load,
                center_step=step,
                cutoff=brush.cutoff(self.model_size),
                mirror_signs=mirror_signs(brush.symmetry),
                origin=self.origin,
                substeps=brush.substeps,
            )
        return active

    # -- constraints -------------------------------------------------------------------------
    @property
    def constraint_points(self) -> np.ndarray:
        """(k, 3) positions of the constraints."""
        return np.zeros((0, 3)) if self._constraints is None else self._constraints.points

    @property
    def constraint_radius(self) -> float:
        """ε of the constraints as a fraction of the model size."""
        return self._constraint_radius

    def _constraint_kernel(self) -> GreenKernel:
        eps = self._constraint_radius * self.model_size
        return self._base_kernel(False).with_radial(self._falloff.with_eps(eps))

    def _rebuild_constraints(self) -> None:
        if self._constraints is None:
            return
        points = self._constraints.points
        self._constraints = ConstraintSet(self._constraint_kernel())
        for p in points:
            self._constraints.add(p)

    def set_constraint_radius(self, radius: float) -> None:
        """ε of the constraints, relative to the model size."""
        radius = Brush(radius=radius).radius
        self._constraint_radius = radius
        self._rebuild_constraints()
        self._log({"op": "constraint_radius", "radius": radius})

    def add_constraint(self, point: np.ndarray) -> int:
        """Pin a point (3,) (model units); returns its index."""
        self._refuse_in_stroke("add a constraint")
        if self._constraints is None:
            self._constraints = ConstraintSet(self._constraint_kernel())
        index = self._constraints.add(point)
        self._log({"op": "constraint_add", "point": np.asarray(point, float).tolist()})
        return index

    def remove_constraint(self, index: int) -> None:
        self._refuse_in_stroke("remove a constraint")
        if self._constraints is None:
            raise ValueError("there are no constraints")
        self._constraints.remove(index)
        self._log({"op": "constraint_remove", "index": int(index)})

    def clear_constraints(self) -> None:
        self._constraints = None
        self._log({"op": "constraints_clear"})

    def drag_constraint(self, index: int, delta: np.ndarray, continued: bool = False) -> np.ndarray:
        """Move constraint ``index`` by ``delta`` (3,) while the others stay: every vertex moves
        by u = Σ_j G(x − p_j) f_j with u(p_index) = delta and u(p_j) = 0. Returns (N, 3) u.

        ``continued``: this step continues the previous drag (one mouse drag = one undo step).
        """
        self._refuse_in_stroke("drag a constraint")
        if self._constraints is None or not 0 <= index < len(self._constraints):
            raise ValueError(f"no constraint {index}")
        d = np.asarray(delta, dtype=np.float64)
        if d.shape != (3,) or not np.all(np.isfinite(d)):
            raise ValueError(f"constraint delta must be 3 finite numbers (got {delta!r})")
        targets = np.zeros((len(self._constraints), 3))
        targets[index] = d
        forces = self._constraints.solve(targets)
        u = self._constraints.displacement(self._vertices, forces)
        start = self._constraints.points[index]
        self._constraints.move(index, start + d)
        before = self._vertices.copy()
        self._vertices += u
        # the pin's own move is undone with the vertices: (index, position) before and after
        pin = ((int(index), start), (int(index), start + d))
        self.history.record_change(
            "constraint drag", before, self._vertices, merge=continued, state=pin
        )
        op = {"op": "constraint_drag", "index": int(index), "delta": d.tolist()}
        self._log({**op, "continued": True} if continued else op)
        return u

    # -- history -----------------------------------------------------------------------------
    def undo(self) -> str | None:
        """Undo the last operation (bit for bit); returns its label or None."""
        self._refuse_in_stroke("undo")
        label = self.history.undo(self._vertices)
        if label is not None:
            self._restore_pin()
            self._log({"op": "undo"})
        return label

    def redo(self) -> str | None:
        self._refuse_in_stroke("redo")
        label = self.history.redo(self._vertices)
        if label is not None:
            self._restore_pin()
            self._log({"op": "redo"})
        return label

    def _restore_pin(self) -> None:
        """Put a dragged pin where the undone/redone drag had it, if that pin still exists."""
        state = self.history.restored_state
        if state is None or self._constraints is None:
            return
        index, point = state
        if index < len(self._constraints):
            with contextlib.suppress(ValueError):  # another pin sits there now: leave it
                self._constraints.move(index, point)

    # -- session log -------------------------------------------------------------------------
    def _log(self, op: dict) -> None:
        # A setting replaces the one logged just before it (a slider or curve drag sets it many
        # times in a row): only the last value can matter to what follows, so replay is unchanged.
        last = self._operations[-1] if self._operations else None
        if op["op"] in _SETTING_OPS and last is not None and last["op"] == op["op"]:
            self._operations[-1] = op
        else:
            self._operations.append(op)

    def session(self) -> dict:
        """The session so far as a JSON-ready dict (see README, "Session files")."""
        return {
            "format": SESSION_FORMAT,
            "version": SESSION_VERSION,
            "mesh": {
                "vertices": len(self._vertices),
                "faces": len(self._faces),
                "sha256": self._fingerprint,
            },
            "settings": self._initial,
            "operations": list(self._operations),
        }

    @classmethod
    def from_session(cls, session: dict, vertices: np.ndarray, faces: np.ndarray) -> Sculptor:
        """A sculptor on ``vertices``/``faces`` with the session's initial settings (no
        operations applied yet; see :meth:`replay`)."""
        if not isinstance(session, dict) or session.get("format") != SESSION_FORMAT:
            raise ValueError(f"not a GoGreen session (expected format {SESSION_FORMAT!r})")
        if session.get("version") != SESSION_VERSION:
            raise ValueError(f"unsupported session version {session.get('version')!r}")
        mesh = session.get("mesh", {})
        if mesh.get("vertices") != len(vertices) or mesh.get("faces") != len(faces):
            raise ValueError(
                f"the session was recorded on a mesh with {mesh.get('vertices')} vertices and "
                f"{mesh.get('faces')} faces; this one has {len(vertices)} and {len(faces)}"
            )
        s = session.get("settings", {})
        try:
            return cls(
                vertices,
                faces,
                material=Material.from_dict(s["material"]),
                l_max=s["l_max"],
                falloff=radial_from_dict(s["falloff"]),
                degree_weights=s["degree_weights"],
            )
        except (KeyError, TypeError) as exc:
            raise ValueError(f"malformed session settings: {exc}") from None

    def replay(
        self, operations: list[dict], progress: Callable[[int, int], None] | None = None
    ) -> None:
        """Apply logged operations in order (the result is bit for bit the recorded one on the
        same machine). ``progress(done, total)`` is called after each mouse event."""
        total = sum(len(op.get("events", ())) or 1 for op in operations)
        done = 0
        for number, op in enumerate(operations):
            try:
                kind = op["op"]
                if kind == "stroke":
                    self.begin_stroke(Brush.from_dict(op["brush"]))
                    for event in op["events"]:
                        self.stroke_event(BrushEvent.from_dict(event))
                        done += 1
                        if progress:
                            progress(done, total)
                    self.end_stroke()
                    continue
                if kind == "material":
                    self.set_material(Material.from_dict(op["material"]))
                elif kind == "falloff":
                    self.set_falloff(
                        radial_from_dict(op["falloff"]), op["l_max"], op["degree_weights"]
                    )
                elif kind == "constraint_radius":
                    self.set_constraint_radius(op["radius"])
                elif kind == "constraint_add":
                    self.add_constraint(op["point"])
                elif kind == "constraint_remove":
                    self.remove_constraint(op["index"])
                elif kind == "constraints_clear":
                    self.clear_constraints()
                elif kind == "constraint_drag":
                    self.drag_constraint(op["index"], op["delta"], bool(op.get("continued")))
                elif kind == "undo":
                    self.undo()
                elif kind == "redo":
                    self.redo()
                else:
                    raise ValueError(f"unknown operation {kind!r}")
            except (KeyError, TypeError) as exc:
                self.cancel_stroke()
                raise ValueError(f"operation {number}: malformed ({exc})") from None
            except ValueError as exc:
                self.cancel_stroke()
                raise ValueError(f"operation {number} ({op.get('op')}): {exc}") from None
            done += 1
            if progress:
                progress(done, total)
