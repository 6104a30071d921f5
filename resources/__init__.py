"""Packaged resources of GoGreen Sculpt: icons, presets and the generated default model."""

from importlib.resources import files
from pathlib import Path


def resource_path(name: str) -> Path:
    """Filesystem path of a packaged resource file, e.g. ``resource_path("default_model.obj")``."""
    return Path(str(files(__name__).joinpath(name)))
