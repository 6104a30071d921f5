"""pyproject.toml: every package folder is installed, and the metadata uses the forms current
setuptools accepts without deprecation warnings."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
SETUPTOOLS = PYPROJECT["tool"]["setuptools"]


def _source_folder(package: str) -> Path:
    """The folder of ``package`` under the package-dir mapping (gogreen_resources → resources)."""
    top, *rest = package.split(".")
    return ROOT / SETUPTOOLS.get("package-dir", {}).get(top, top) / Path(*rest)


def _package_folders(top: str) -> set[str]:
    """Dotted names of ``top`` and of every folder below it that holds a module or data file
    (setuptools warns about, and a wheel leaves out, a folder absent from ``packages``)."""
    base = _source_folder(top)
    found = set()
    for folder in [base, *(p for p in base.rglob("*") if p.is_dir())]:
        if folder.name == "__pycache__" or any(p.name.startswith(".") for p in folder.parents):
            continue
        if any(f.is_file() and not f.name.endswith(".pyc") for f in folder.iterdir()):
            found.add(".".join([top, *folder.relative_to(base).parts]))
    return found


def test_every_package_folder_is_listed():
    listed = set(SETUPTOOLS["packages"])
    for top in {name.split(".")[0] for name in listed}:
        missing = _package_folders(top) - listed
        assert not missing, f"add {sorted(missing)} to [tool.setuptools] packages"
    for name in listed:
        assert _source_folder(name).is_dir(), name


def test_data_folders_ship_their_files():
    package_data = SETUPTOOLS["package-data"]
    for name in SETUPTOOLS["packages"]:
        folder = _source_folder(name)
        data = [f for f in folder.iterdir() if f.is_file() and f.suffix not in (".py", ".pyc")]
        for file in data:
            patterns = package_data.get(name, [])
            assert any(file.match(p) for p in patterns), f"{file} is not in package-data"


def test_license_is_an_spdx_string_with_a_setuptools_that_reads_it():
    # A TOML table (`{ text = "MIT" }`) makes setuptools ≥ 77 print a deprecation box on
    # every install; the string form needs setuptools ≥ 77 to build.
    assert PYPROJECT["project"]["license"] == "MIT"
    (requirement,) = [r for r in PYPROJECT["build-system"]["requires"] if "setuptools" in r]
    match = re.fullmatch(r"setuptools>=(\d+)(\.\d+)*", requirement.replace(" ", ""))
    assert match and int(match.group(1)) >= 77
    classifiers = PYPROJECT["project"].get("classifiers", [])
    assert not [c for c in classifiers if c.startswith("License ::")]  # refused beside SPDX
