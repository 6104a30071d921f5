"""``counted``: GreenKernel.streamlines with the velocity evaluations each point took
(``from streamline_counts import counted``; pytest puts ``tests/helpers`` on the path)."""

from __future__ import annotations

from typing import Any

import numpy as np

from gogreen_core import GreenKernel


def counted(
    kernel: GreenKernel, points: np.ndarray, center: np.ndarray, load: np.ndarray, **options: Any
) -> tuple[np.ndarray, np.ndarray]:
    """(end positions, evaluations (n,) int64) of one ``kernel.streamlines`` call."""
    indices = options.get("indices")
    evaluations = np.empty(len(points) if indices is None else len(indices), dtype=np.int64)
    result = kernel.streamlines(points, center, load, evaluations=evaluations, **options)
    return result, evaluations
