"""What the Material panel's inputs hold, as an evented model (no Qt).

:class:`MaterialForm` has one field per input of the panel: the input ``mode`` (isotropic,
orthotropic, transversely isotropic, full Voigt), ``lame`` (the isotropic page uses λ, μ instead
of E, ν), the constants of every page, the Voigt table and the rotation of the material axes.
The form always describes a valid material: an edit that would make an invalid one is refused
with a :class:`~gogreen_core.validation.ParameterError` naming the input as the panel names it
("Poisson ratio ν must lie in (-1, 1/2)"), and the panel's widgets, bound to the form
(:mod:`app.bindings`), show the refusal. :func:`form_values` goes the other way: the inputs that
show a given material in the mode that fits it (isotropic, transversely isotropic about z,
orthotropic in the axes x, y, z, else the Voigt table).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from app.bindings import panel_words
from gogreen_core.interaction.settings import EventedModel, Field
from gogreen_core.physics.material import Material
from gogreen_core.validation import ParameterError

__all__ = [
    "FIELD_SPECS",
    "ISOTROPIC_EN",
    "ISOTROPIC_LAME",
    "MODES",
    "MODE_TITLES",
    "ORTHOTROPIC",
    "TRANSVERSE",
    "FieldSpec",
    "MaterialForm",
    "build_material",
    "form_values",
    "isotropic_parameters",
]

#: Mode keys, in the order of the mode selector.
MODES = ("isotropic", "orthotropic", "transversely_isotropic", "voigt")
MODE_TITLES = {
    "isotropic": "Isotropic",
    "orthotropic": "Orthotropic (axes x, y, z)",
    "transversely_isotropic": "Transversely isotropic (axis z)",
    "voigt": "Full 6×6 stiffness (Voigt)",
}
#: Entries below this fraction of the largest count as zero when the type is recognized.
_TOLERANCE = 1e-9


@dataclass(frozen=True)
class FieldSpec:
    key: str
    label: str
    default: float
    tooltip: str
    #: Parameter names (ParameterError.parameter, or words of a plain ValueError's message)
    #: that point at this field.
    keywords: tuple[str, ...]
    minimum: float = -1e300
    maximum: float = 1e300


ISOTROPIC_EN = (
    FieldSpec("young", "Young's modulus E", 1.0, "Stiffness E > 0 (any unit)", ("young", "E")),
    FieldSpec(
        "poisson",
        "Poisson ratio ν",
        0.3,
        "Lateral contraction, -1 < ν < 1/2 (0.5 = incompressible)",
        ("poisson",),
        -10.0,
        10.0,
    ),
)
ISOTROPIC_LAME = (
    FieldSpec("lam", "Lamé λ", 0.576923, "First Lamé parameter; need 3λ + 2μ > 0", ("lam",)),
    FieldSpec("mu", "Shear modulus μ", 0.384615, "Second Lamé parameter μ > 0", ("mu",)),
)
ORTHOTROPIC = (
    FieldSpec("E1", "E1", 1.0, "Young's modulus along x", ("E1",)),
    FieldSpec("E2", "E2", 1.0, "Young's modulus along y", ("E2",)),
    FieldSpec("E3", "E3", 3.0, "Young's modulus along z", ("E3",)),
    FieldSpec("G23", "G23", 0.5, "Shear modulus in the yz plane", ("G23",)),
    FieldSpec("G13", "G13", 0.5, "Shear modulus in the xz plane", ("G13",)),
    FieldSpec("G12", "G12", 0.4, "Shear modulus in the xy plane", ("G12",)),
    FieldSpec("nu12", "ν12", 0.25, "Contraction along y under stress along x", ("nu12",)),
    FieldSpec("nu13", "ν13", 0.1, "Contraction along z under stress along x", ("nu13",)),
    FieldSpec("nu23", "ν23", 0.1, "Contraction along z under stress along y", ("nu23",)),
)
TRANSVERSE = (
    FieldSpec("young_plane", "In-plane E_p", 1.0, "Young's modulus in the xy plane", ("E1", "E2")),
    FieldSpec("young_axial", "Axial E_z", 3.0, "Young's modulus along the axis z", ("E3",)),
    FieldSpec(
        "poisson_plane",
        "In-plane ν_p",
        0.3,
        "In-plane contraction under in-plane stress, |ν_p| < 1",
        ("poisson_plane", "nu12"),
    ),
    FieldSpec(
        "poisson_axial",
        "Axial ν_pz",
        0.1,
        "Contraction along z under in-plane stress",
        ("poisson_axial", "nu13", "nu23"),
    ),
    FieldSpec(
        "shear_axial",
        "Axial shear G_z",
        0.5,
        "Shear modulus of planes containing z (G13 = G23)",
        ("G23", "G13"),
    ),
)
FIELD_SPECS = {s.key: s for s in (*ISOTROPIC_EN, *ISOTROPIC_LAME, *ORTHOTROPIC, *TRANSVERSE)}
#: How the core's messages name a field, and the name the panel shows instead.
_MESSAGE_NAMES = {
    "young (Young's modulus)": "Young's modulus E",
    "Young's modulus E1": "E1",
    "Young's modulus E2": "E2",
    "Young's modulus E3": "E3",
    "shear modulus mu": "Shear modulus μ",
    **{s.key: s.label for s in FIELD_SPECS.values()},
}


def _mode_keys(values: dict[str, Any]) -> list[str]:
    """The keys of the inputs the material is built from in ``values``' mode."""
    mode = values["mode"]
    if mode == "isotropic":
        return [s.key for s in (ISOTROPIC_LAME if values["lame"] else ISOTROPIC_EN)]
    if mode == "orthotropic":
        return [s.key for s in ORTHOTROPIC]
    if mode == "transversely_isotropic":
        return [s.key for s in TRANSVERSE]
    return ["voigt"]


def _base(values: dict[str, Any]) -> Material:
    """The material (before rotation) of the inputs ``values`` (ValueError when invalid)."""
    f = values
    mode = f["mode"]
    if mode == "isotropic":
        if f["lame"]:
            return Material.from_lame(f["lam"], f["mu"])
        return Material.isotropic(f["young"], f["poisson"])
    if mode == "orthotropic":
        return Material.orthotropic(
            young=(f["E1"], f["E2"], f["E3"]),
            shear=(f["G23"], f["G13"], f["G12"]),
            poisson=(f["nu12"], f["nu13"], f["nu23"]),
        )
    if mode == "transversely_isotropic":
        return Material.transversely_isotropic(
            young_plane=f["young_plane"],
            young_axial=f["young_axial"],
            poisson_plane=f["poisson_plane"],
            poisson_axial=f["poisson_axial"],
            shear_axial=f["shear_axial"],
        )
    return Material.from_voigt(f["voigt"])


def rotation_matrix(angles: tuple[float, float, float]) -> np.ndarray:
    """``Rz(γ) Ry(β) Rx(α)`` (3, 3) of Euler angles (α, β, γ) in degrees."""
    return Rotation.from_euler("xyz", angles, degrees=True).as_matrix()


def build_material(values: dict[str, Any]) -> tuple[Material, Material]:
    """(base, rotated) materials of the inputs ``values`` (ValueError when invalid)."""
    base = _base(values)
    if all(a == 0.0 for a in values["angles"]):
        return base, base
    return base, base.rotated(rotation_matrix(values["angles"]))


def _mentions(message: str, keywords: tuple[str, ...]) -> bool:
    return any(
        re.search(rf"(?<![A-Za-z0-9_]){re.escape(k)}(?![A-Za-z0-9_])", message) for k in keywords
    )


def _number(_form: EventedModel, name: str, value: Any) -> float:
    label = FIELD_SPECS[name].label
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, f"{label}: {value!r} is not a number") from None
    if not np.isfinite(number):
        raise ParameterError(name, f"{label} must be a finite number (got {value!r})")
    return number


def _mode(_form: EventedModel, name: str, value: Any) -> str:
    if value not in MODES:
        raise ParameterError(name, f"mode must be one of {', '.join(MODES)} (got {value!r})")
    return str(value)


def _flag(_form: EventedModel, _name: str, value: Any) -> bool:
    return bool(value)


def _voigt(_form: EventedModel, name: str, value: Any) -> np.ndarray:
    try:
        voigt = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(
            name, "the stiffness table holds something that is not a number"
        ) from None
    if voigt.shape != (6, 6) or not np.all(np.isfinite(voigt)):
        raise ParameterError(name, "the stiffness table needs 6×6 finite numbers")
    voigt.setflags(write=False)
    return voigt


def _angles(_form: EventedModel, name: str, value: Any) -> tuple[float, float, float]:
    angles = tuple(float(a) for a in value)
    if len(angles) != 3 or not all(np.isfinite(angles)):
        raise ParameterError(name, f"rotation: three finite angles in degrees (got {value!r})")
    return angles  # type: ignore[return-value]


class _FormBase(EventedModel):
    mode = Field("isotropic", _mode, doc="input mode, one of MODES")
    lame = Field(False, _flag, doc="the isotropic page uses λ, μ (else E, ν)")
    voigt = Field(lambda: Material.isotropic(1.0, 0.3).voigt, _voigt, doc="(6, 6) table")
    angles = Field((0.0, 0.0, 0.0), _angles, doc="Euler angles α, β, γ in degrees")

    def _normalize(self, values: dict[str, Any]) -> dict[str, Any]:
        out = super()._normalize(values)
        if not self._values:
            return out  # construction: the defaults are valid
        merged = {**self._values, **out}
        if out.get("mode") == "voigt" and self._values["mode"] != "voigt" and "voigt" not in out:
            # the 6×6 table continues from the current base stiffness (the switch changes
            # nothing), keeping the exact entries it holds when they are that stiffness
            base = self.base_material
            if not _rebuilds(base, {**self._values, "mode": "voigt"}):
                out["voigt"] = merged["voigt"] = _voigt(self, "voigt", base.voigt)
        pairs = {"young", "poisson", "lam", "mu"}
        if "lame" in out and out["lame"] != self._values["lame"] and not pairs & set(out):
            out.update(_converted_pair(self, bool(out["lame"])))
            merged.update(out)
        try:
            build_material(merged)
        except ValueError as exc:
            raise _refusal(exc, set(values), _mode_keys(merged)) from None
        return out

    @property
    def base_material(self) -> Material:
        """The material of the inputs, before the rotation of its axes."""
        return build_material(self._values)[0]

    @property
    def material(self) -> Material:
        """The material of the inputs (rotation applied)."""
        return build_material(self._values)[1]


def _refusal(exc: ValueError, edited: set[str], keys: list[str]) -> ParameterError:
    """``exc`` as a ParameterError about the input it names (one of ``keys``, the inputs of
    the mode; preferably one just ``edited``), in the panel's words."""
    parameter = getattr(exc, "parameter", None)
    if parameter is not None and parameter in keys:
        offending = [parameter]
    else:
        offending = [
            k for k in keys if k != "voigt" and _mentions(str(exc), FIELD_SPECS[k].keywords)
        ]
    chosen = next((k for k in offending if k in edited), None)
    key = chosen or (offending[0] if offending else next(iter(edited & set(keys)), keys[0]))
    return ParameterError(key, panel_words(str(exc), _MESSAGE_NAMES))


def _converted_pair(form: _FormBase, lame: bool) -> dict[str, float]:
    """The other isotropic pair of the current one, so that toggling E, ν ↔ λ, μ keeps the
    material: λ = C12, μ = C44, E = 1 / S11, ν = -S12 / S11 (nothing when it is invalid)."""
    values = form.values()
    try:
        if lame:
            base = Material.isotropic(values["young"], values["poisson"])
            return {"lam": float(base.voigt[0, 1]), "mu": float(base.voigt[3, 3])}
        base = Material.from_lame(values["lam"], values["mu"])
        s = base.compliance
        return {"young": float(1.0 / s[0, 0]), "poisson": float(-s[0, 1] / s[0, 0])}
    except ValueError:
        return {}


#: The form's class: one number field per input (FIELD_SPECS) besides the fields above.
MaterialForm: type[_FormBase] = type(
    "MaterialForm",
    (_FormBase,),
    {
        "__doc__": "The Material panel's inputs (see the module docstring).",
        **{key: Field(spec.default, _number, doc=spec.label) for key, spec in FIELD_SPECS.items()},
    },
)


def isotropic_parameters(material: Material) -> dict[str, float] | None:
    """E, ν, λ and μ of an isotropic ``material`` (to round-off), else None."""
    c = np.asarray(material.voigt, dtype=np.float64)
    scale = float(np.max(np.abs(c)))
    if scale == 0.0 or not np.all(np.isfinite(c)):
        return None
    lam, mu = c[0, 1], c[3, 3]
    expected = np.zeros((6, 6))
    expected[:3, :3] = lam
    expected[np.arange(3), np.arange(3)] = lam + 2 * mu
    expected[np.arange(3, 6), np.arange(3, 6)] = mu
    if np.max(np.abs(c - expected)) > _TOLERANCE * scale or lam + mu == 0:
        return None
    young = mu * (3 * lam + 2 * mu) / (lam + mu)
    poisson = lam / (2 * (lam + mu))
    return {"young": young, "poisson": poisson, "lam": lam, "mu": mu}


def _orthotropic_constants(material: Material) -> dict[str, float] | None:
    """The nine engineering constants of a material orthotropic in the axes x, y, z, else
    None (coupling between normal and shear entries, or between shears)."""
    c = np.asarray(material.voigt, dtype=np.float64)
    scale = float(np.max(np.abs(c)))
    coupling = c.copy()
    coupling[:3, :3] = 0.0
    coupling[np.arange(3, 6), np.arange(3, 6)] = 0.0
    if scale == 0.0 or np.max(np.abs(coupling)) > _TOLERANCE * scale:
        return None
    s = material.compliance
    e1, e2, e3 = 1.0 / s[0, 0], 1.0 / s[1, 1], 1.0 / s[2, 2]
    return {
        "E1": e1,
        "E2": e2,
        "E3": e3,
        "G23": 1.0 / s[3, 3],
        "G13": 1.0 / s[4, 4],
        "G12": 1.0 / s[5, 5],
        "nu12": -s[0, 1] * e1,
        "nu13": -s[0, 2] * e1,
        "nu23": -s[1, 2] * e2,
    }


def _rebuilds(material: Material, values: dict[str, Any]) -> bool:
    """Whether the inputs ``values`` make ``material`` again (to round-off)."""
    try:
        rebuilt = _base(values)
    except ValueError:
        return False
    scale = float(np.max(np.abs(material.voigt)))
    return bool(np.max(np.abs(rebuilt.voigt - material.voigt)) <= 1e-9 * scale)


def form_values(material: Material, lame: bool = False) -> dict[str, Any]:
    """The inputs that show ``material`` (rotation zero) in the first mode that fits it:
    isotropic (E, ν, or λ, μ with ``lame``), transversely isotropic about z, orthotropic in
    the axes x, y, z, else the Voigt table. The Voigt table always holds the material."""
    values: dict[str, Any] = {"voigt": material.voigt, "angles": (0.0, 0.0, 0.0)}
    isotropic = isotropic_parameters(material)
    if isotropic is not None:
        return {**values, **isotropic, "mode": "isotropic", "lame": lame}
    ortho = _orthotropic_constants(material)
    if ortho is not None:
        transverse = {
            "young_plane": ortho["E1"],
            "young_axial": ortho["E3"],
            "poisson_plane": ortho["nu12"],
            "poisson_axial": ortho["nu13"],
            "shear_axial": ortho["G23"],
        }
        candidate = {**values, **transverse, "mode": "transversely_isotropic"}
        if _rebuilds(material, candidate):
            return candidate
        candidate = {**values, **ortho, "mode": "orthotropic"}
        if _rebuilds(material, candidate):
            return candidate
    return {**values, "mode": "voigt"}
