"""Headless command line: ``gogreen replay``, ``gogreen deform``, ``gogreen truncation`` and
``gogreen recover`` (no Qt imported).

    gogreen replay SESSION.json IN -o OUT
    gogreen deform IN -o OUT --brush grab --center X Y Z --delta DX DY DZ [--radius R] ...
    gogreen truncation [--material FILE | --young E --poisson NU] [--l-max L] [--max-degree D]
    gogreen recover --list | ID [-o OUT] [--session OUT.json] [--discard]

They print a progress bar on stderr, and on bad input exit with status 2 and a one-line message
naming the problem; the output file is written atomically (a failure never leaves half a file).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import replace
from datetime import datetime
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from gogreen_core.field.limits import check_l_max
from gogreen_core.field.truncation import truncation_errors
from gogreen_core.files.journal import recovery_root
from gogreen_core.files.recovery import (
    discard,
    find_journal,
    journal_session,
    list_journals,
    read_journal,
    recover,
)
from gogreen_core.mesh.mesh_io import MeshData, load_mesh, save_mesh, write_text_atomic
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import GaussianRadial, KelvinletRadial, RadialProfile
from gogreen_core.sculpt.brushes import (
    BRUSH_KINDS,
    DEFAULT_INFLUENCE,
    MAX_AMOUNT,
    Brush,
    BrushEvent,
)
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.operations import MAX_EVENTS
from gogreen_core.sculpt.schema import parse_falloff, parse_material, read_json
from gogreen_core.sculpt.sculptor import Sculptor
from gogreen_core.sculpt.session import load_session
from gogreen_core.sculpt.setting_table import Setting, rows
from gogreen_core.validation import (
    ParameterError,
    check_integer,
    check_number,
    check_vector,
    prefixed,
)

__all__ = ["main"]

T = TypeVar("T")


class ProgressBar:
    """A text progress bar on stderr (redrawn in place on a terminal, else every 10%)."""

    WIDTH = 30

    def __init__(self, label: str) -> None:
        self.label = label
        self.start = time.perf_counter()
        self._last_decile = -1

    def __call__(self, done: int, total: int) -> None:
        fraction = done / total if total else 1.0
        filled = round(self.WIDTH * fraction)
        text = (
            f"{self.label} [{'#' * filled}{'.' * (self.WIDTH - filled)}] {done}/{total} "
            f"{time.perf_counter() - self.start:.1f} s"
        )
        if sys.stderr.isatty():
            sys.stderr.write("\r" + text + ("\n" if done >= total else ""))
        elif int(10 * fraction) != self._last_decile:
            self._last_decile = int(10 * fraction)
            sys.stderr.write(text + "\n")
        sys.stderr.flush()


def _save(mesh: MeshData, sculptor: Sculptor, path: str) -> None:
    """The sculptor's mesh (its faces and UVs too) to ``path``; ``mesh``, the file read: its
    texture coordinates must reach the output (a sculptor made without them is a bug here)."""
    now = sculptor.mesh
    if mesh.uv is not None and now.uv is None:
        raise RuntimeError("internal error: the texture coordinates of the input were dropped")
    save_mesh(MeshData(now.vertices, now.faces, now.uv, now.uv_faces, mesh.source), path)


def _replay(args: argparse.Namespace) -> int:
    session = load_session(args.session)  # every field checked before the mesh is read
    mesh = load_mesh(args.input)
    sculptor = Sculptor.from_session(session, mesh.vertices, mesh.faces, mesh.uv, mesh.uv_faces)
    if session.sha256 is not None and session.sha256 != sculptor.session()["mesh"]["sha256"]:
        print(
            f"gogreen: warning: {args.input} differs from the mesh the session was recorded on",
            file=sys.stderr,
        )
    try:
        sculptor.replay(session, ProgressBar("replay") if not args.quiet else None)
    except ParameterError as exc:  # found while applying (a pin index that does not exist)
        name = Path(args.session).name
        raise ParameterError(exc.parameter, f"{name}: {exc}") from None
    _save(mesh, sculptor, args.output)
    return 0


def _from_file(path: str, option: str, key: str, parse: Callable[[object, str], T]) -> T:
    """``parse`` of the JSON in file ``path`` given to ``option``: a preset's ``key`` section,
    or a bare file; ValueError naming the option."""
    try:
        data = read_json(path)
    except ValueError as exc:
        raise ValueError(f"{option} {exc}") from None
    section = ""
    if isinstance(data, dict) and key in data and data.get("format") == "gogreen-preset":
        data, section = data[key], key
    with prefixed(option):
        return parse(data, section)


def _material(args: argparse.Namespace) -> Material:
    if args.material:
        return _from_file(args.material, "--material", "material", parse_material)
    with prefixed("--young/--poisson"):
        return Material.isotropic(args.young, args.poisson)


def _falloff(name: str) -> RadialProfile:
    if name in ("gaussian", "kelvinlet"):
        return GaussianRadial(1.0) if name == "gaussian" else KelvinletRadial(1.0)
    return _from_file(name, "--falloff", "falloff", parse_falloff)


def _deform_stroke(args: argparse.Namespace) -> tuple[EngineSettings, Brush, BrushEvent, int]:
    """The settings, brush, first event and event count of ``gogreen deform`` (the drag split
    into equal events, as mouse events of one stroke), every option checked under its name."""
    values = {s.name: s.check(getattr(args, s.name), s.flag) for s in _flag_rows()}
    settings = EngineSettings(material=_material(args), falloff=_falloff(args.falloff), **values)
    with _option_names():
        brush = Brush(
            args.brush, args.radius, args.strength, args.substeps, args.influence, args.symmetry
        )
    center = check_vector("--center", args.center)
    delta = check_vector("--delta", args.delta)
    amount = check_number("--amount", args.amount, low=-MAX_AMOUNT, high=MAX_AMOUNT)
    axis = None if args.axis is None else check_vector("--axis", args.axis)
    direction = None if args.direction is None else check_vector("--direction", args.direction)
    events = check_integer("--events", args.events, low=1, high=MAX_EVENTS)
    paint = brush.type.family == "paint"  # smooth, mask: --amount is each event's pressure
    if (brush.is_affine or paint) and amount == 0:
        raise ParameterError("--amount", f"the {brush.kind} brush needs --amount (nonzero)")
    if not (brush.is_affine or paint) and not np.any(delta):
        raise ParameterError("--delta", f"the {brush.kind} brush needs --delta (nonzero)")
    share = amount if paint else amount / events
    with _option_names():
        return settings, brush, BrushEvent(center, delta / events, share, axis, direction), events


def _deform(args: argparse.Namespace) -> int:
    mesh = load_mesh(args.input)
    settings, brush, first, events = _deform_stroke(args)
    sculptor = Sculptor(
        mesh.vertices, mesh.faces, uv=mesh.uv, uv_faces=mesh.uv_faces, settings=settings
    )
    progress = None if args.quiet else ProgressBar("deform")
    sculptor.begin_stroke(brush)
    try:
        for k in range(events):
            with _option_names():
                sculptor.stroke_event(replace(first, center=first.center + k * first.delta))
            if progress:
                progress(k + 1, events)
    except Exception:
        sculptor.cancel_stroke()
        raise
    sculptor.end_stroke()
    _save(mesh, sculptor, args.output)
    if args.session_out:
        write_text_atomic(args.session_out, json.dumps(sculptor.session(), indent=1))
    return 0


def _truncation(args: argparse.Namespace) -> int:
    """Print δ(l_max) of the material, one line per even l_max, then the summary."""
    material = _material(args)
    l_max = check_l_max(args.l_max, "--l-max")
    max_degree = check_integer("--max-degree", args.max_degree, low=0, high=44)
    progress = None if args.quiet else ProgressBar("truncation")
    report = truncation_errors(material, max_degree, progress=progress)
    print("relative error of the Green's function within 6 ε, by l_max:")
    print(report.table())
    print(report.summary(l_max))
    return 0


def _recover(args: argparse.Namespace) -> int:
    root = recovery_root()
    if args.list:
        _print_journals(root)
        return 0
    if not args.journal:
        raise ValueError("name a journal (see --list), or give --list")
    if not (args.output or args.session or args.discard):
        raise ValueError("say what to do: -o OUT.obj, --session OUT.json and/or --discard")
    directory = find_journal(args.journal, root)
    if args.output or args.session:
        _write_recovered(directory, args)
    if args.discard:
        discard(directory)
        print(f"discarded {directory.name}", file=sys.stderr)
    else:
        print(
            f"the journal stays in {directory} (`gogreen recover {directory.name} --discard` "
            "deletes it)",
            file=sys.stderr,
        )
    return 0


def _print_journals(root: Path) -> None:
    infos = list_journals(root)
    if not infos:
        print(f"no recovery journals in {root}")
        return
    print(f"{'ID':<24} {'LAST CHANGE':<19} {'OPS':>5}  DOCUMENT")
    for info in infos:
        when = datetime.fromtimestamp(info.modified).strftime("%Y-%m-%d %H:%M:%S")
        document = info.document or "(no file: the default model)"
        print(f"{info.id:<24} {when:<19} {info.operations:>5}  {info.title} — {document}")
        print(f"{'':<24} {info.vertices:,} vertices; {info.summary()}")
        if info.status():
            print(f"{'':<24} {info.status()}")
    print(f"\njournals live in {root}")


def _write_recovered(directory: Path, args: argparse.Namespace) -> None:
    if args.output:
        recovery = recover(directory, progress=None if args.quiet else ProgressBar("recover"))
        try:
            _save(recovery.mesh, recovery.sculptor, args.output)
        finally:
            recovery.release()
        contents, notes = recovery.contents, recovery.notes
        print(
            f"recovered {contents.title}: {len(contents.operations)} operations "
            f"({recovery.records} records; {recovery.replayed} replayed in "
            f"{recovery.seconds:.1f} s) -> {args.output}",
            file=sys.stderr,
        )
    else:
        contents = read_journal(directory)
        notes = contents.notes
    for note in notes:
        print(f"gogreen recover: warning: {note}", file=sys.stderr)
    if args.session:
        session = journal_session(contents)
        write_text_atomic(args.session, json.dumps(session, indent=1))
        count = len(session["operations"])
        print(f"wrote the session ({count} operations) -> {args.session}", file=sys.stderr)


@contextmanager
def _option_names() -> Iterator[None]:
    """Re-raise a ParameterError of a brush or event field under its option's name
    (``delta`` → ``--delta``), so the message names what the user typed."""
    try:
        yield
    except ParameterError as exc:
        if not exc.parameter.isidentifier():
            raise
        option, message = "--" + exc.parameter.replace("_", "-"), str(exc)
        if message.startswith(exc.parameter):
            message = option + message[len(exc.parameter) :]
        else:
            message = f"{option}: {message}"
        raise ParameterError(option, message) from None


def _flag_rows() -> tuple[Setting, ...]:
    """The setting table's ``"cli"`` rows that are one flag each (not the material and
    falloff: ``--material``, ``--young``, ``--poisson``, ``--falloff``)."""
    return tuple(s for s in rows("cli") if s.type in ("int", "float", "bool", "choice"))


def _add_setting_flags(parser: argparse.ArgumentParser) -> None:
    """One flag per :func:`_flag_rows` row, its default and help from the table."""
    for s in _flag_rows():
        if s.type == "bool":
            action = argparse.BooleanOptionalAction
            parser.add_argument(s.flag, action=action, default=s.initial(), help=s.doc)
        else:
            kind = {"int": int, "float": float}.get(s.type, str)
            choices = s.choices or None
            parser.add_argument(s.flag, type=kind, choices=choices, default=s.initial(), help=s.doc)


def _vector_flag(parser: argparse.ArgumentParser, flag: str, help: str, **options: Any) -> None:
    parser.add_argument(flag, type=float, nargs=3, metavar=("X", "Y", "Z"), help=help, **options)


def _material_flags(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--material", help="material JSON (Material.to_dict or a preset)")
    parser.add_argument("--young", type=float, default=1.0)
    parser.add_argument("--poisson", type=float, default=0.3)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="gogreen", description="GoGreen Sculpt, headless")
    sub = parser.add_subparsers(dest="command", required=True)
    replay = sub.add_parser("replay", help="replay a session file on a mesh")
    replay.add_argument("session", help="session JSON written by the app or `deform`")
    replay.add_argument("input", help="mesh the session starts from (OBJ, PLY, STL, OFF)")
    replay.add_argument("-o", "--output", required=True, help="where to write the result")
    replay.set_defaults(run=_replay)

    deform = sub.add_parser("deform", help="apply one brush stroke to a mesh")
    deform.add_argument("input")
    deform.add_argument("-o", "--output", required=True)
    deform.add_argument("--brush", choices=BRUSH_KINDS, default="grab")
    _vector_flag(deform, "--center", "the brush centre", required=True)
    _vector_flag(deform, "--delta", "grab displacement (model units)", default=[0.0, 0.0, 0.0])
    deform.add_argument(
        "--amount",
        type=float,
        default=0.0,
        help="affine brushes: log strain or angle (radians) at the centre, split over --events; "
        "smooth and mask: each event's pressure (negative: the mask brush erases)",
    )
    _vector_flag(deform, "--axis", "twist axis / pinch normal (default +z)")
    _vector_flag(deform, "--direction", "pinch stretch direction")
    deform.add_argument("--radius", type=float, default=0.1, help="ε / model size")
    deform.add_argument("--strength", type=float, default=1.0)
    deform.add_argument("--substeps", type=int, default=0, help="RK4 steps (0: adaptive)")
    deform.add_argument(
        "--influence",
        type=float,
        default=DEFAULT_INFLUENCE,
        help="influence radius in multiples of ε ('inf' for all vertices)",
    )
    deform.add_argument("--symmetry", default="", help="mirror planes, e.g. x or xz")
    deform.add_argument("--events", type=int, default=1, help="split the stroke into N events")
    _material_flags(deform)
    deform.add_argument(
        "--falloff", default="gaussian", help="gaussian, kelvinlet, or a falloff/preset JSON file"
    )
    _add_setting_flags(deform)
    deform.add_argument("--session-out", help="also write the session JSON here")
    deform.set_defaults(run=_deform)

    truncation = sub.add_parser(
        "truncation", help="how accurate each l_max is for a material (paper Fig. 9)"
    )
    _material_flags(truncation)
    truncation.add_argument("--l-max", type=int, default=8, help="the l_max to assess")
    truncation.add_argument("--max-degree", type=int, default=20, help="largest l_max measured")
    truncation.set_defaults(run=_truncation)
    recover_ = sub.add_parser(
        "recover",
        help="list the crash-recovery journals, or rebuild what one recorded",
        description=(
            "List the crash-recovery journals, or rebuild the mesh (and session) one recorded. "
            f"Journals live in {recovery_root()}."
        ),
    )
    recover_.add_argument("journal", nargs="?", help="journal ID (or its first characters)")
    recover_.add_argument("--list", action="store_true", help="list the journals")
    recover_.add_argument(
        "-o", "--output", help="write the recovered mesh (.obj, .ply, .stl, .off)"
    )
    recover_.add_argument("--session", help="write the journal's operations as a session JSON")
    recover_.add_argument("--discard", action="store_true", help="delete the journal")
    recover_.set_defaults(run=_recover)
    for command in (replay, deform, truncation, recover_):
        command.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run a batch command; returns the exit status (2 on bad input)."""
    args = _parser().parse_args(argv)
    try:
        return int(args.run(args))
    except (ValueError, RuntimeError, OSError) as exc:  # MeshFileError, JournalError: ValueError
        print(f"gogreen {args.command}: error: {exc}", file=sys.stderr)
        return 2
