"""What the fuzz tests (tests/core/interaction/test_fuzz_parsers.py, short, Hypothesis) and the long
run (benchmarks/fuzz.py) feed the parsers, and the rule every input must keep.

A target is one parser: the mesh readers (OBJ, PLY ASCII and binary, STL ASCII and binary,
OFF), the session, preset and journal parsers and the command line's argument parsing. Each has
seed inputs (valid files made here) and a ``run`` that parses one input. The rule: an input
either loads into a finite, in-range value (checked here) or is refused with a ``ValueError``
whose message names the file (or, for the command line, the option); any other exception is a
failure. Mutations are plain byte and token edits, the same in both runs.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import io
import json
import math
import random
import struct
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.mesh.mesh_io import MeshData, save_mesh
from gogreen_core.mesh.mesh_io.data import validate_mesh
from gogreen_core.mesh.mesh_io.formats import _READERS
from gogreen_core.mesh.shapes import icosphere


@dataclass
class Target:
    """One parser under fuzzing."""

    name: str
    seeds: list[bytes]
    #: Parse one input in ``folder`` (a scratch folder of its own); raise ValueError to refuse.
    run: Callable[[bytes, Path], None]
    #: What a refusal's message must start with or contain (the file's name, an option).
    names: tuple[str, ...]


class Failure(Exception):
    """An input broke the rule: another exception, a value out of range, an anonymous error."""


# -- seeds -------------------------------------------------------------------------------------
def _small_mesh() -> MeshData:
    """An icosphere (42 vertices) with texture coordinates, and two of its triangles merged
    into a quad where the files keep polygons."""
    vertices, faces = icosphere(1)
    uv = np.stack([vertices[:, 0] * 0.5 + 0.5, vertices[:, 1] * 0.5 + 0.5], axis=1)
    return MeshData(vertices, faces, uv, faces.copy())


def _saved(mesh: MeshData, suffix: str, folder: Path, **options: bool) -> bytes:
    path = folder / f"seed{suffix}"
    save_mesh(mesh, path, **options)
    return path.read_bytes()


def _ascii_stl(mesh: MeshData) -> bytes:
    rows = ["solid seed"]
    for corners in mesh.vertices[mesh.faces].tolist():
        rows += ["facet normal 0 0 1", "outer loop"]
        rows += [f"vertex {x!r} {y!r} {z!r}" for x, y, z in corners]
        rows += ["endloop", "endfacet"]
    return ("\n".join([*rows, "endsolid seed"]) + "\n").encode()


_OBJ_EXTRA = (
    b"# quirks\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1 1.0\nvt 0 0\nvt 1 0\nvt 1 1\n"
    b"vn 0 0 1\ng part\nusemtl m\nf 1/1/1 2/2/1 3/3/1 4/1/1\nf -5 -4 -1\nl 1 2\ns off\n"
    b"f 1//1 3//1 5//1\n"
)
_PLY_EXTRA = (
    b"ply\nformat ascii 1.0\ncomment x\nelement vertex 5\nproperty float x\nproperty float y\n"
    b"property float z\nproperty uchar red\nelement face 2\n"
    b"property list uchar int vertex_indices\nelement edge 1\nproperty int vertex1\n"
    b"property int vertex2\nend_header\n0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n0.5 0.5 1 5\n"
    b"4 0 1 2 3\n3 0 1 4\n0 1\n"
)
_OFF_EXTRA = b"OFF\n# c\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n4 0 1 2 3 255 0 0\n3 0 1 4\n"


def mesh_seeds(folder: Path) -> dict[str, list[bytes]]:
    mesh = _small_mesh()
    plain = MeshData(mesh.vertices, mesh.faces)
    return {
        "obj": [_saved(mesh, ".obj", folder), _OBJ_EXTRA],
        "ply-ascii": [_saved(mesh, ".ply", folder, ascii=True), _PLY_EXTRA],
        "ply-binary": [_saved(mesh, ".ply", folder), _saved(plain, ".ply", folder)],
        "stl-ascii": [_ascii_stl(plain)],
        "stl-binary": [_saved(plain, ".stl", folder)],
        "off": [_saved(plain, ".off", folder), _OFF_EXTRA],
    }


def _sculpted() -> Sculptor:
    vertices, faces = icosphere(1)
    sculptor = Sculptor(vertices, faces, l_max=4)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    sculptor.apply_brush(Brush("grab", radius=0.3), [BrushEvent(top, [0.0, 0.0, 0.05])])
    sculptor.apply_brush(Brush("smooth", radius=0.3), [BrushEvent(top, amount=0.5)])
    return sculptor


def session_seeds() -> list[bytes]:
    return [json.dumps(_sculpted().session(), indent=1).encode()]


def preset_seeds() -> list[bytes]:
    from gogreen_core.files.presets import builtin_presets

    return [json.dumps(p.to_dict(), indent=1).encode() for p in builtin_presets()[:2]]


def journal_seeds(folder: Path) -> list[bytes]:
    from gogreen_core.files.journal import Journal
    from gogreen_core.files.journal_format import JOURNAL_FILE

    vertices, faces = icosphere(1)
    sculptor = Sculptor(vertices, faces, l_max=4)
    journal = Journal(sculptor, MeshData(vertices, faces), root=folder / "journals")
    top = vertices[int(np.argmax(vertices[:, 2]))]
    sculptor.apply_brush(Brush("grab", radius=0.3), [BrushEvent(top, [0.0, 0.0, 0.05])])
    sculptor.undo()
    journal.flush()
    assert journal.directory is not None
    data = (journal.directory / JOURNAL_FILE).read_bytes()
    journal.close()
    return [data]


CLI_SEEDS = [
    "deform in.obj -o out.obj --center 0 0 1 --delta 0 0 0.1",
    "deform in.ply -o out.ply --brush twist --center 0 0 1 --amount 0.3 --axis 0 0 1 --events 3",
    "deform in.ply -o o.ply --brush smooth --center 0 0 1 --amount 1 --radius 0.2 --symmetry xz",
    "deform in.stl -o o.stl --brush pinch --center 1 0 0 --amount -0.2 --direction 0 1 0 "
    "--young 2 --poisson 0.45 --l-max 6 --falloff kelvinlet --influence inf --substeps 2",
    "truncation --young 1 --poisson 0.3 --l-max 8 --max-degree 12",
    "replay s.json in.obj -o out.obj -q",
    "recover --list",
]
_CLI_WORDS = [
    "--center", "--delta", "--amount", "--axis", "--direction", "--radius", "--strength",
    "--substeps", "--influence", "--symmetry", "--events", "--young", "--poisson", "--l-max",
    "--falloff", "--brush", "--max-degree", "--material", "-o", "-q", "--list", "--discard",
    "nan", "inf", "-inf", "0", "-0", "1e308", "1e-320", "-1", "99999999999999999999", "0.5",
    "auto", "grab", "twist", "mask", "smooth", "scale", "xyz", "q", "", "--", "-", "x",
]  # fmt: skip


# -- the rule ----------------------------------------------------------------------------------
def _finite(name: str, value: object) -> None:
    """Raise Failure if ``value`` holds a non-finite float anywhere (a parsed value)."""
    if isinstance(value, float) and not math.isfinite(value):
        raise Failure(f"{name}: non-finite value {value!r} accepted")
    if isinstance(value, np.ndarray) and value.dtype.kind == "f" and not np.isfinite(value).all():
        raise Failure(f"{name}: non-finite array accepted")


def _mesh_target(name: str, suffix: str, seeds: list[bytes]) -> Target:
    file_name = f"fuzz{suffix}"

    def run(data: bytes, folder: Path) -> None:
        if not data or data.isspace():
            return  # load_mesh refuses an empty file before any reader sees it
        mesh = _READERS[suffix](data, file_name)
        # As load_mesh does: a mesh with a non-finite coordinate or an index out of range is
        # refused naming the file and the vertex or face (a binary file has no lines).
        validate_mesh(mesh, file_name)
        if not (np.isfinite(mesh.vertices).all() and len(mesh.faces)):
            raise Failure("a non-finite or empty mesh passed validate_mesh")

    return Target(name, seeds, run, (file_name,))


def _json_target(name: str, seeds: list[bytes], load: Callable[[Path], object]) -> Target:
    def run(data: bytes, folder: Path) -> None:
        path = folder / "fuzz.json"
        path.write_bytes(data)
        _finite(name, load(path))

    return Target(name, seeds, run, ("fuzz.json",))


def _load_session(path: Path) -> object:
    from gogreen_core.sculpt.session import load_session

    session = load_session(path)
    for op in session.operations:
        for event in getattr(op, "events", ()):
            for value in (event.center, event.delta, event.acting_amount):
                _finite("session", value)
    return session.vertices


def _load_preset(path: Path) -> object:
    from gogreen_core.files.presets import load_preset

    preset = load_preset(path)
    return preset.brush.radius


def _journal_target(seeds: list[bytes]) -> Target:
    from gogreen_core.files.journal_format import JOURNAL_FILE, read_journal

    def run(data: bytes, folder: Path) -> None:
        directory = folder / "fuzz-journal"
        directory.mkdir(exist_ok=True)
        (directory / JOURNAL_FILE).write_bytes(data)
        contents = read_journal(directory)
        for record in contents.records:
            if not isinstance(record.seq, int) or record.seq < 1:
                raise Failure(f"journal: record numbered {record.seq!r} accepted")

    return Target("journal", seeds, run, ("fuzz-journal",))


@functools.cache
def _cli_parser() -> argparse.ArgumentParser:
    """The command line's parser, made once (parsing leaves it as it was)."""
    from gogreen_core.interaction import batch

    return batch._parser()


def _cli_run(data: bytes, folder: Path) -> None:
    from gogreen_core.interaction import batch

    argv = data.decode("utf-8", "replace").split(" ")
    with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
        try:
            args = _cli_parser().parse_args(argv)
        except SystemExit as exc:  # argparse's refusal (status 2), or the help asked for (0)
            asked = any(
                (len(a) > 2 and "--help".startswith(a))  # --h, --he: argparse's abbreviations
                or (a[:1] == "-" != a[1:2] and "h" in a)  # -h, or in a cluster: -qh
                for a in argv
            )
            if exc.code != (0 if asked and exc.code == 0 else 2):
                raise Failure(f"argparse exited with {exc.code!r}") from None
            return
    if args.command == "deform":
        first = batch._deform_stroke(args)[2]
        for value in (first.center, first.delta, first.amount):
            _finite("deform", value)
    elif args.command == "truncation":
        batch._material(args)
        batch.check_l_max(args.l_max, "--l-max")


def targets(folder: Path) -> list[Target]:
    """Every parser under fuzzing, its seeds made in ``folder``."""
    meshes = mesh_seeds(folder)
    suffixes = {"obj": ".obj", "ply-ascii": ".ply", "ply-binary": ".ply", "stl-ascii": ".stl",
                "stl-binary": ".stl", "off": ".off"}  # fmt: skip
    found = [_mesh_target(name, suffixes[name], seeds) for name, seeds in meshes.items()]
    found += [
        _json_target("session", session_seeds(), _load_session),
        _json_target("preset", preset_seeds(), _load_preset),
        _journal_target(journal_seeds(folder)),
        Target("command line", [s.encode() for s in CLI_SEEDS], _cli_run, ("--", "-o")),
    ]
    return found


def check(target: Target, data: bytes, folder: Path) -> str | None:
    """None when ``data`` keeps the rule, else what went wrong."""
    try:
        target.run(data, folder)
    except Failure as exc:
        return str(exc)
    except ValueError as exc:
        message = str(exc)
        if not any(name in message for name in target.names) and target.name != "command line":
            return f"refused without naming the file: {message!r}"
        return None
    except RecursionError:
        return "RecursionError"
    except Exception as exc:  # the point: nothing else may escape
        return f"{type(exc).__name__}: {exc}"
    return None


# -- mutations ---------------------------------------------------------------------------------
_INTERESTING = [b"nan", b"inf", b"-inf", b"-1", b"0", b"-0", b"1e999", b"1e-320", b"4294967296",
                b"99999999999999999999", b"2147483648", b"255", b"3", b"4", b"0x10", b"1,5",
                b"\xff\xfe", b"\x00", b"null", b"true", b"[]", b"{}", b'"x"', b"1e308"]  # fmt: skip


def mutate(data: bytes, rng: random.Random, seeds: list[bytes]) -> bytes:
    """One to four random edits of ``data``: byte flips, inserts, deletions, truncation,
    duplicated or spliced ranges, numbers swapped for edge values, and (for JSON and journal
    lines) the same within a payload re-framed with a valid checksum."""
    out = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        n = len(out)
        kind = rng.randrange(9)
        at = rng.randrange(n + 1)
        if kind == 0 and n:
            out[min(at, n - 1)] ^= 1 << rng.randrange(8)
        elif kind == 1:
            out[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        elif kind == 2 and n:
            del out[at : at + rng.randint(1, 64)]
        elif kind == 3:
            del out[at:]
        elif kind == 4 and n:
            end = min(n, at + rng.randint(1, 200))
            out[at:at] = out[at:end] * rng.randint(1, 3)
        elif kind == 5:
            other = rng.choice(seeds)
            start = rng.randrange(len(other) + 1)
            out[at:] = other[start : start + rng.randint(0, 400)] + out[at:]
        elif kind in (6, 7):
            tokens = list(_number_spans(out))
            if tokens:
                start, end = rng.choice(tokens)
                out[start:end] = rng.choice(_INTERESTING)
        elif kind == 8 and n >= 4 and rng.random() < 0.5:
            struct.pack_into("<I", out, min(at, n - 4), rng.choice([0, 1, 2**31, 2**32 - 1]))
    return bytes(out)


def _number_spans(data: bytearray) -> list[tuple[int, int]]:
    import re

    return [m.span() for m in re.finditer(rb"-?\d+(\.\d+)?([eE][-+]?\d+)?", data[:20000])]


def reframed(data: bytes, rng: random.Random, seeds: list[bytes]) -> bytes:
    """A journal with one line's payload mutated and its checksum made valid again (so the
    mutation reaches the JSON and operation parsers, not just the checksum test)."""
    from gogreen_core.files.journal_format import frame

    lines = data.split(b"\n")
    index = rng.randrange(max(1, len(lines) - 1))
    line = lines[index]
    payload = line[9:] if len(line) > 9 else line
    lines[index] = frame(mutate(payload, rng, [payload]))[:-1]
    return b"\n".join(lines)
