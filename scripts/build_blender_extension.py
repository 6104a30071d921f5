"""Build the GoGreen Sculpt extension for Blender 4.2+: one installable .zip per platform and
Blender Python.

Usage (``bash scripts/build_blender_extension.sh`` runs it with .venv's Python, or any
Python >= 3.11 with pip)::

    bash scripts/build_blender_extension.sh                     # every platform -> dist/
    bash scripts/build_blender_extension.sh --platform linux-x64

Each package holds ``gogreen_blender/`` (the add-on), its ``blender_manifest.toml`` with the
``platforms`` and ``wheels`` entries filled in, and ``wheels/``: ``gogreen_core`` built from
this checkout (with the built-in presets) and, from the package index, numba, llvmlite, scipy,
trimesh and mapbox_earcut for that platform and one Python that Blender versions ship (3.11:
Blender 4.2 to 5.0; 3.13: 5.1 on), resolved against the numpy that Blender bundles (so numpy
itself is not included). A package holds one Python's wheels only (half the download and the
install of one holding both) and its manifest names the Blender versions of that Python
(``blender_version_min`` / ``blender_version_max``), so Blender refuses the other one:
``dist/gogreen_sculpt-<version>-<platform>-cp311.zip`` and ``...-cp313.zip``.

The packages are then checked with Blender's own validator (``blender_ext.py validate`` from
the ``bpy`` package of ``.venv-blender``, ``--blender-ext PATH``, or a ``blender`` on the
PATH); without any of those a smaller check of the manifest runs and says so.

Downloads are kept in ``build/blender/wheels`` and reused by later builds.
"""

from __future__ import annotations

import argparse
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SOURCE = ROOT / "gogreen_blender"
MANIFEST = "blender_manifest.toml"

#: Blender platform -> pip platform tags its wheels may have (pip accepts older macOS too).
PLATFORMS = {
    "linux-x64": ("manylinux_2_28_x86_64", "manylinux2014_x86_64"),
    "windows-x64": ("win_amd64",),
    "macos-x64": ("macosx_11_0_x86_64",),
    "macos-arm64": ("macosx_12_0_arm64",),  # scipy >= 1.15 needs macOS 12 on arm64
}
#: Python version of Blender's builds -> the numpy requirement they bundle (what the bpy
#: package of that Python requires: bpy 4.2-5.0 numpy<2 on 3.11, bpy 5.1+ numpy>=2.2 on 3.13),
#: resolved at its lowest so that the chosen scipy and numba accept it.
PYTHONS = {"3.11": "numpy==1.26.4", "3.13": "numpy==2.2.6"}
#: Python version -> the Blender versions that ship it: (first, first after; None: open).
BLENDER_VERSIONS = {"3.11": ("4.2.0", "5.1.0"), "3.13": ("5.1.0", None)}
#: What the add-on needs besides numpy (gogreen_core's dependencies).
REQUIREMENTS = ("numba>=0.60", "scipy>=1.15", "trimesh>=4.0", "mapbox-earcut>=1.0.3")
#: Files of the add-on folder that go into the package.
ADDON_FILES = "*.py"


def log(message: str) -> None:
    print(f"[blender-extension] {message}", flush=True)


def version() -> str:
    """The project's version (pyproject.toml), which the manifest must carry too."""
    with open(ROOT / "pyproject.toml", "rb") as fh:
        project = tomllib.load(fh)["project"]["version"]
    with open(SOURCE / MANIFEST, "rb") as fh:
        manifest = tomllib.load(fh)["version"]
    if manifest != project:
        sys.exit(f"{SOURCE / MANIFEST}: version {manifest} differs from pyproject.toml's {project}")
    return project


def core_packages() -> list[str]:
    """The packages of ``gogreen_core`` and its presets, as pyproject.toml lists them (so that a
    new subpackage of the core, such as ``gogreen_core.mesh.mesh_io``, is in the wheel too)."""
    with open(ROOT / "pyproject.toml", "rb") as fh:
        listed = tomllib.load(fh)["tool"]["setuptools"]["packages"]
    wanted = ("gogreen_core", "gogreen_resources", "gogreen_resources.presets")
    return [p for p in listed if p in wanted or p.startswith("gogreen_core.")]


def pip(*args: str) -> None:
    subprocess.run([sys.executable, "-m", "pip", *args], check=True)


def core_wheel(out: Path, project_version: str) -> Path:
    """Build the ``gogreen_core`` wheel (with the presets of ``gogreen_resources``) into
    ``out`` from a staged copy of the checkout's sources."""
    with tempfile.TemporaryDirectory() as tmp:
        stage = Path(tmp)
        ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "*.nbi", "*.nbc")
        shutil.copytree(ROOT / "gogreen_core", stage / "gogreen_core", ignore=ignore)
        resources = stage / "gogreen_resources"
        (resources / "presets").mkdir(parents=True)
        shutil.copy2(ROOT / "resources" / "__init__.py", resources)
        for preset in (ROOT / "resources" / "presets").glob("*.json"):
            shutil.copy2(preset, resources / "presets")
        (stage / "pyproject.toml").write_text(
            f"""[build-system]
requires = ["setuptools>=68"]
build-backend = "setuptools.build_meta"

[project]
name = "gogreen-core"
version = "{project_version}"
description = "GoGreen Sculpt's engine: regularized Green's functions of elasticity"
requires-python = ">=3.11"
dependencies = ["numpy>=1.26", "scipy>=1.15", "numba>=0.60", "trimesh>=4.0",
                "mapbox-earcut>=1.0.3"]

[tool.setuptools]
packages = {core_packages()!r}

[tool.setuptools.package-data]
"gogreen_resources.presets" = ["*.json"]
"""
        )
        for old in out.glob("gogreen_core-*.whl"):
            old.unlink()
        pip("wheel", "--quiet", "--no-deps", "--wheel-dir", str(out), str(stage))
    (wheel,) = out.glob("gogreen_core-*.whl")
    return wheel


def download(platform: str, python: str, cache: Path) -> list[Path]:
    """The dependency wheels of one platform and Python (numpy left out: Blender has it)."""
    folder = cache / f"{platform}-cp{python.replace('.', '')}"
    folder.mkdir(parents=True, exist_ok=True)
    tags = [arg for tag in PLATFORMS[platform] for arg in ("--platform", tag)]
    log(f"wheels for {platform}, Python {python}")
    pip(
        "download",
        "--quiet",
        "--only-binary=:all:",
        *tags,
        "--python-version",
        python,
        "--implementation",
        "cp",
        "--dest",
        str(folder),
        *REQUIREMENTS,
        PYTHONS[python],
    )
    wheels = sorted(folder.glob("*.whl"))
    return [w for w in wheels if not w.name.startswith("numpy-")]


def newest_per_project(wheels: list[Path]) -> list[Path]:
    """One wheel per project and Python tag (a cache folder may keep older downloads)."""

    def key(path: Path) -> tuple:
        name, _ver, *_rest, py, _abi, _plat = path.stem.split("-")
        return name.lower(), py

    def version_key(path: Path) -> tuple:
        ver = path.stem.split("-")[1]
        return tuple(int(p) if p.isdigit() else 0 for p in ver.split("."))

    best: dict[tuple, Path] = {}
    for wheel in wheels:
        k = key(wheel)
        if k not in best or version_key(wheel) > version_key(best[k]):
            best[k] = wheel
    return sorted(best.values())


def _toml_list(values: list[str]) -> str:
    return "[\n" + "".join(f'  "{v}",\n' for v in values) + "]"


def python_tag(python: str) -> str:
    """'3.11' -> 'cp311' (the wheels' tag, and the package name's)."""
    return "cp" + python.replace(".", "")


def package(
    platform: str, python: str, wheels: list[Path], out: Path, project_version: str
) -> Path:
    """Write ``dist/gogreen_sculpt-<version>-<platform>-<cpXY>.zip``: the wheels of one
    platform and Python, the Blender versions of that Python in its manifest."""
    manifest = (SOURCE / MANIFEST).read_text()
    first, after = BLENDER_VERSIONS[python]
    head, sep, tail = manifest.partition("[permissions]")
    head = re.sub(r'(?m)^blender_version_min = ".*"$', f'blender_version_min = "{first}"', head)
    versions = f'blender_version_max = "{after}"\n' if after else ""
    names = [f"./wheels/{w.name}" for w in wheels]
    manifest = (
        f"{head.rstrip()}\n{versions}\nplatforms = {_toml_list([platform])}\n"
        f"wheels = {_toml_list(names)}\n\n{sep}{tail}"
    )
    out.mkdir(parents=True, exist_ok=True)
    name = f"gogreen_sculpt-{project_version}-{platform.replace('-', '_')}-{python_tag(python)}"
    target = out / f"{name}.zip"
    partial = target.with_name(target.name + ".partial")
    with zipfile.ZipFile(partial, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        zf.writestr(MANIFEST, manifest)
        for source in sorted(SOURCE.glob(ADDON_FILES)):
            zf.write(source, source.name)
        for wheel in wheels:  # already compressed
            zf.write(wheel, f"wheels/{wheel.name}", compress_type=zipfile.ZIP_STORED)
    os.replace(partial, target)
    size = target.stat().st_size / 2**20
    log(f"{target.relative_to(ROOT) if target.is_relative_to(ROOT) else target} ({size:.0f} MB)")
    return target


def find_blender_validator(explicit: str | None) -> list[str] | None:
    """The command that runs Blender's extension validator, or None."""
    if explicit:
        return [sys.executable, explicit]
    pattern = ".venv-blender/lib/python3*/site-packages/bpy/*/scripts/addons_core/bl_pkg/cli"
    for cli in sorted(glob.glob(str(ROOT / pattern))):
        return [sys.executable, str(Path(cli) / "blender_ext.py")]
    blender = shutil.which("blender")
    if blender:
        return [blender, "--factory-startup", "--command", "extension"]
    return None


def validate(packages: list[Path], validator: list[str] | None) -> None:
    """Blender's own validation of each package, or a basic check of its manifest."""
    for pkg in packages:
        if validator is not None:
            result = subprocess.run(
                [*validator, "validate", str(pkg)], capture_output=True, text=True
            )
            output = (result.stdout + result.stderr).strip()
            if result.returncode != 0:
                sys.exit(f"Blender's validation of {pkg.name} failed:\n{output}")
            log(f"validated by Blender: {pkg.name}: {output.splitlines()[-1]}")
            continue
        with zipfile.ZipFile(pkg) as zf:
            manifest = tomllib.loads(zf.read(MANIFEST).decode())
            missing = [w for w in manifest["wheels"] if w[2:] not in zf.namelist()]
        required = ("schema_version", "id", "version", "name", "type", "blender_version_min")
        absent = [key for key in required if key not in manifest]
        if missing or absent:
            sys.exit(f"{pkg.name}: missing wheels {missing} or manifest keys {absent}")
        log(f"{pkg.name}: manifest read (Blender's validator not found: no .venv-blender)")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--platform",
        action="append",
        choices=sorted(PLATFORMS),
        help="build for this platform only (repeatable; default: all)",
    )
    parser.add_argument(
        "--python",
        action="append",
        choices=sorted(PYTHONS),
        help="build the package of this Blender Python only (repeatable; default: all)",
    )
    parser.add_argument("--output", type=Path, default=ROOT / "dist", help="default: dist/")
    parser.add_argument(
        "--cache", type=Path, default=ROOT / "build" / "blender" / "wheels", help="downloads"
    )
    parser.add_argument("--blender-ext", help="path of Blender's blender_ext.py validator")
    args = parser.parse_args(argv)
    project_version = version()
    platforms = args.platform or list(PLATFORMS)
    pythons = args.python or list(PYTHONS)
    args.cache.mkdir(parents=True, exist_ok=True)
    core = core_wheel(args.cache, project_version)
    log(f"built {core.name}")
    packages = []
    for platform in platforms:
        for python in pythons:
            deps = newest_per_project(download(platform, python, args.cache))
            packages.append(package(platform, python, [core, *deps], args.output, project_version))
    validate(packages, find_blender_validator(args.blender_ext))
    return 0


if __name__ == "__main__":
    sys.exit(main())
