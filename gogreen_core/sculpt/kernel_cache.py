"""The kernels of one engine-settings value, each built once, and what brushes derive from them
(memoized by a key of their choosing: sampled field bounds, reach)."""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Any, TypeVar

import numpy as np

from gogreen_core.field.kernel import GreenKernel
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.falloff_safety import mean_green_direction

__all__ = ["KernelCache"]

T = TypeVar("T")
#: Derived values kept per settings (field bounds of brush shapes and influence radii); the
#: memo is emptied when it would hold more.
MAX_DERIVED = 16


class KernelCache:
    """Kernels (ε = 1, the settings' falloff shape) of ``settings``.

    previous : the cache of the settings before, whose quadrature is reused when the
        material and l_max are the same (a falloff edit builds new radial tables only).
    """

    def __init__(self, settings: EngineSettings, previous: KernelCache | None = None) -> None:
        self.settings = settings
        if previous is not None and previous.settings.agrees(settings, ("l_max", "material")):
            self.full: GreenKernel = previous.full.with_radial(settings.falloff)  # same quadrature
        else:
            self.full = GreenKernel(settings.material, settings.l_max, settings.falloff)
        self._weighted: dict[bytes, GreenKernel] = {}
        self._derived: dict[Hashable, Any] = {}

    #: The rotation F (3, 3) these kernels' material is turned by from the settings' (a stroke's
    #: surface frame, :class:`~gogreen_core.sculpt.material_frame.FramedKernels`); None here.
    frame: np.ndarray | None = None

    @property
    def unturned(self) -> KernelCache:
        """The kernels of the settings' material as it is (these): what values that turn with
        the material or do not depend on its orientation are computed on."""
        return self

    def weighted(self, weights: np.ndarray | None) -> GreenKernel:
        """The kernel with per-degree ``weights`` (l_max + 1,) on its field (paper Fig. 10),
        or :attr:`full` for None."""
        if weights is None:
            return self.full
        key = np.asarray(weights, dtype=np.float64).tobytes()
        kernel = self._weighted.get(key)
        if kernel is None:
            kernel = self._weighted[key] = self.full.with_degree_weights(weights)
        return kernel

    def derived(self, key: Hashable, make: Callable[[], T]) -> T:
        """``make()`` once per ``key`` for these settings (e.g. a sampled field bound)."""
        if key in self._derived:
            return self._derived[key]  # type: ignore[no-any-return]
        if len(self._derived) >= MAX_DERIVED:
            self._derived.clear()
        value = make()
        self._derived[key] = value
        return value

    @property
    def green_scale(self) -> float:
        """‖A‖ (:func:`mean_green_direction`): G's size for this material at ε = 1 up to a
        falloff factor of order 1."""
        material = self.settings.material
        return self.derived(
            "green scale", lambda: float(np.linalg.norm(mean_green_direction(material), 2))
        )
