"""Matcap shading: the surface coloured by a lit sphere's picture looked up by the view-space
normal (Blender's and ZBrush's "material capture"), so forms read at any angle.

The pictures are made here, at first use (a few milliseconds each), from a small lighting
recipe each: no image files. :func:`matcap_image` gives one as an (H, W, 3) uint8 array (row 0
the top), :func:`matcap_texture` as a VTK texture, and :func:`use_matcap` puts one on a mesh
actor: its fragment shader's lighting is replaced by a lookup of the texture at the normal's
view-space x, y (the pixel of the lit sphere with that normal), times the vertex colour (the
mask, cavity and field-preview tints multiply it). It works with software OpenGL (llvmpipe): a
texture and a shader replacement, no extension.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np
import pyvista as pv

from app.mesh_display import MODEL_RGB
from gogreen_core.interaction.settings import MATCAPS

__all__ = ["MATCAP_RECIPES", "MATCAP_SIZE", "MatcapRecipe", "matcap_image", "use_matcap"]

#: Side of a matcap picture in pixels.
MATCAP_SIZE = 256


@dataclass(frozen=True)
class MatcapRecipe:
    """How a matcap's sphere is lit (colours as displayed, RGB in [0, 1]).

    title : the View menu's text.
    base : the surface colour.
    key : direction towards the key light (view space: x right, y up, z to the viewer).
    wrap : diffuse wrap in [0, 1] (0 Lambert; more: light bleeds past the terminator, waxy).
    ambient : light that reaches every normal.
    fill : weight of a dim fill light from the lower right.
    specular, shininess : highlight weight and Phong exponent of the key light.
    highlight : the highlight's colour.
    rim : weight of a light rim at grazing normals (0: none; < 0 darkens the rim).
    sky : weight of a horizon reflection (a glossy surface mirrors a bright sky, dark floor).
    """

    title: str
    base: tuple[float, float, float]
    key: tuple[float, float, float] = (-0.45, 0.6, 0.66)
    wrap: float = 0.0
    ambient: float = 0.12
    fill: float = 0.2
    specular: float = 0.0
    shininess: float = 20.0
    highlight: tuple[float, float, float] = (1.0, 1.0, 1.0)
    rim: float = 0.0
    sky: float = 0.0


#: The matcaps of the View menu, in its order (the first is the default): a grey clay that
#: shows form best, ZBrush's red wax, a glossy dark one and Blender's plain "basic".
MATCAP_RECIPES: dict[str, MatcapRecipe] = {
    "clay": MatcapRecipe(
        "Clay", (0.80, 0.76, 0.70), wrap=0.3, ambient=0.22, fill=0.2, specular=0.1,
        shininess=12.0, rim=-0.25,
    ),
    "red_wax": MatcapRecipe(
        "Red Wax", (0.78, 0.2, 0.13), wrap=0.55, ambient=0.18, fill=0.15, specular=0.45,
        shininess=28.0, highlight=(1.0, 0.85, 0.75), rim=0.25,
    ),
    "glossy": MatcapRecipe(
        "Glossy", (0.22, 0.26, 0.32), ambient=0.06, fill=0.12, specular=1.0, shininess=90.0,
        rim=0.1, sky=0.35,
    ),
    "basic": MatcapRecipe(
        "Basic", (0.82, 0.82, 0.82), key=(0.0, 0.75, 0.66), ambient=0.25, fill=0.1,
        specular=0.08, shininess=8.0,
    ),
}  # fmt: skip
if set(MATCAP_RECIPES) != set(MATCAPS):  # the settings model declares the names
    raise RuntimeError(
        "app.matcaps: a recipe for each of gogreen_core.interaction.settings.MATCAPS"
    )


def _unit(v: tuple[float, float, float]) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    return a / np.linalg.norm(a)


@cache
def matcap_image(name: str, size: int = MATCAP_SIZE) -> np.ndarray:
    """The lit sphere of matcap ``name`` (a key of :data:`MATCAP_RECIPES`): (size, size, 3)
    uint8 RGB, row 0 at the top; pixel (row, col) shows the normal with view-space
    x = 2 (col + ½) / size − 1, y = 1 − 2 (row + ½) / size (outside the disc: the rim's)."""
    recipe = MATCAP_RECIPES[name]
    t = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    x, y = np.meshgrid(t, -t)
    r2 = np.minimum(x * x + y * y, 1.0)
    scale = np.where(x * x + y * y > 1.0, 1.0 / np.sqrt(x * x + y * y), 1.0)
    n = np.stack([x * scale, y * scale, np.sqrt(1.0 - r2)], axis=-1)
    key, fill = _unit(recipe.key), _unit((0.6, -0.45, 0.66))
    wrap = recipe.wrap
    diffuse = np.clip((n @ key + wrap) / (1.0 + wrap), 0.0, 1.0)
    diffuse += recipe.fill * np.clip(n @ fill, 0.0, 1.0)
    base = np.asarray(recipe.base)
    color = base * (recipe.ambient + (1.0 - recipe.ambient) * diffuse)[..., None]
    view = np.array([0.0, 0.0, 1.0])
    reflect = 2.0 * n[..., 2:3] * n - view  # the view ray mirrored by the surface
    spec = np.clip(reflect @ key, 0.0, 1.0) ** recipe.shininess
    color += recipe.specular * spec[..., None] * np.asarray(recipe.highlight)
    grazing = (1.0 - n[..., 2]) ** 3
    color += recipe.rim * grazing[..., None] * (base if recipe.rim < 0 else np.ones(3))
    if recipe.sky:
        horizon = 0.5 + 0.5 * np.tanh(6.0 * reflect[..., 1])  # bright above, dark below
        color += recipe.sky * (horizon * (0.3 + 0.7 * n[..., 2] ** 0.5))[..., None]
    return np.ascontiguousarray(np.rint(255 * np.clip(color, 0.0, 1.0)).astype(np.uint8))


#: The mesh actor's lighting replaced by the matcap lookup: the view-space normal's x, y pick the
#: lit sphere's pixel; the vertex or property colour over the model's colour (1 where nothing
#: tints it: the mask, cavity and field preview tints are ratios to it) multiplies it.
_MODEL_VEC3 = "vec3({:.6f}, {:.6f}, {:.6f})".format(*(MODEL_RGB / 255.0))
_FRAGMENT = f"""//VTK::Light::Impl
  {{
    vec2 matcapUV = normalize(normalVCVSOutput).xy * 0.495 + 0.5;
    vec3 matcap = texture(actortexture, matcapUV).rgb;
    vec3 tint = diffuseColor / max(diffuseIntensity, 1e-3) / {_MODEL_VEC3};
    fragOutput0 = vec4(clamp(matcap * tint, 0.0, 1.0), opacity);
  }}
"""


def matcap_texture(name: str) -> Any:
    """Matcap ``name`` as a new VTK texture (linear filtering, clamped). Not shared: a texture
    holds its render window's graphics resources."""
    texture = pv.Texture(matcap_image(name))  # pyvista flips row 0 to the top
    texture.SetInterpolate(True)
    texture.SetRepeat(False)
    texture.SetEdgeClamp(True)
    return texture


def use_matcap(actor: Any, name: str | None) -> None:
    """Shade ``actor`` (a mesh actor with point normals) with matcap ``name``; None: back to
    VTK's lighting. Its colours (the property's or the vertices') over
    :data:`app.mesh_display.MODEL_RGB` multiply the picture."""
    shader = actor.GetShaderProperty()
    shader.ClearAllFragmentShaderReplacements()
    if name is None:
        actor.SetTexture(None)
        return
    actor.SetTexture(matcap_texture(name))
    shader.AddFragmentShaderReplacement("//VTK::Light::Impl", True, _FRAGMENT, False)
