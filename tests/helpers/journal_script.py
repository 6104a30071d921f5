"""A deterministic sculpting session for the crash-recovery tests, and the child process that
runs it under a journal until the test kills it (tests/core/files/test_journal_sigkill.py).

    python tests/helpers/journal_script.py

reads ``ROOT SEED [--slow]`` lines on its input and forks a process for each (the imports are
done once: each session starts in a few ms), which prints ``PID p``, ``READY``, then ``START k``
before each step and ``DONE r`` after it (r: journal records written), then waits to be killed;
the forking process prints ``EXIT p`` when it is gone. With ``--slow`` every journal line is
written in 48-byte pieces 0.2 ms apart after a ``W`` line, and every checkpoint in 1 kB pieces
1 ms apart after a ``C`` line, so that a kill lands in the middle of a write (a disk that slow
is what a crash during a write looks like). Nothing here starts a thread before the fork.
"""

from __future__ import annotations

import hashlib
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from gogreen_core import Brush, BrushEvent, Material, Sculptor
from gogreen_core.mesh.mesh_io import MeshData
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.physics.radial import GaussianRadial, KelvinletRadial

#: Steps of one session.
STEPS = 36


def mesh() -> MeshData:
    vertices, faces = icosphere(3)
    return MeshData(vertices=vertices, faces=faces)


def fingerprint(sculptor: Sculptor) -> str:
    """SHA-256 of the vertices, the pins and the settings (what recovery must give back)."""
    digest = hashlib.sha256(np.ascontiguousarray(sculptor.vertices).tobytes())
    digest.update(np.ascontiguousarray(sculptor.constraint_points).tobytes())
    digest.update(repr(sculptor.settings.to_dict()).encode())
    return digest.hexdigest()


def steps(sculptor: Sculptor, seed: int) -> list[Callable[[], None]]:
    """``STEPS`` operations (strokes, pins, settings drags, undos and redos) drawn from
    ``seed``; each is one call, so each adds at most one journal record."""
    rng = np.random.default_rng(seed)
    vertices = sculptor.vertices.copy()
    kinds = ["grab", "grab", "grab_biscale", "twist", "scale", "grab"]
    out: list[Callable[[], None]] = []

    def stroke() -> None:
        kind = kinds[rng.integers(len(kinds))]
        brush = Brush(
            kind, radius=0.15 + 0.1 * rng.random(), symmetry="x" if rng.random() < 0.3 else ""
        )
        center = vertices[rng.integers(len(vertices))]
        events = []
        for k in range(int(rng.integers(3, 12))):
            if brush.is_affine:
                events.append(
                    BrushEvent(center, amount=0.05 * rng.standard_normal(), axis=[0, 0, 1])
                )
            else:
                delta = 0.01 * rng.standard_normal(3)
                events.append(BrushEvent(center + k * delta, delta))
        out.append(lambda: sculptor.apply_brush(brush, events))

    def pin() -> None:
        point = vertices[rng.integers(len(vertices))]
        out.append(lambda: sculptor.add_constraint(point))

    def drag() -> None:
        index = int(rng.integers(4))
        for k in range(int(rng.integers(1, 4))):
            delta = 0.01 * rng.standard_normal(3)
            out.append(
                lambda d=delta, c=k > 0: (
                    len(sculptor.constraint_points) > index
                    and sculptor.drag_constraint(index, d, continued=c)
                )
            )

    def settings() -> None:
        if rng.random() < 0.5:
            for k in range(int(rng.integers(1, 4))):
                material = Material.isotropic(1.0, 0.1 + 0.3 * rng.random())
                out.append(
                    lambda m=material, c=k > 0: sculptor.change_settings(material=m, continued=c)
                )
        elif rng.random() < 0.5:
            falloff = KelvinletRadial(1.0) if rng.random() < 0.5 else GaussianRadial(1.0)
            out.append(lambda: sculptor.change_settings(falloff=falloff))
        else:
            radius = 0.05 + 0.1 * rng.random()
            out.append(lambda: sculptor.change_settings(constraint_radius=radius))

    def history() -> None:
        for _ in range(int(rng.integers(1, 4))):
            out.append(lambda: sculptor.undo())
        if rng.random() < 0.5:
            out.append(lambda: sculptor.redo())

    makers = [stroke] * 5 + [pin, drag, drag, settings, history, history]
    while len(out) < STEPS:
        makers[rng.integers(len(makers))]()
    return out[:STEPS]


def run(sculptor: Sculptor, seed: int, after: Callable[[int], None]) -> None:
    """Do the session's steps; ``after(step)`` follows each. A refused step (a pin too close to
    another) is part of the session: it refuses the same way every time."""
    for number, step in enumerate(steps(sculptor, seed)):
        try:
            step()
        except ValueError:
            pass
        after(number)


def say(line: str) -> None:
    """One whole line on the standard output (one write: the worker thread says C meanwhile)."""
    os.write(1, (line + "\n").encode())


def _slow_writes() -> None:
    """Write journal lines and checkpoints slowly, saying when a write starts (W, C)."""
    import gogreen_core.files.journal as journal
    import gogreen_core.sculpt.checkpoint as checkpoint

    def write_all(fd: int, data: bytes) -> None:
        say("W")
        for start in range(0, len(data), 48):
            journal._write_piece(fd, data[start : start + 48])
            time.sleep(0.0002)

    class Slow:
        def __init__(self, out) -> None:
            self.out = out

        def write(self, data) -> None:
            data = memoryview(data).cast("B")
            for start in range(0, len(data), 1024):
                self.out.write(data[start : start + 1024])
                self.out.flush()
                time.sleep(0.001)

    original = checkpoint.atomic_write

    def atomic_write(path, write) -> None:
        say("C")
        original(path, lambda out: write(Slow(out)))

    journal._write_piece = journal.write_all
    journal.write_all = write_all
    checkpoint.atomic_write = atomic_write


def session(argv: list[str]) -> None:
    from gogreen_core.files.journal import Journal

    say(f"PID {os.getpid()}")
    root, seed, slow = Path(argv[0]), int(argv[1]), "--slow" in argv
    if slow:
        _slow_writes()
    data = mesh()
    sculptor = Sculptor(data.vertices, data.faces)
    journal = Journal(sculptor, data, root=root, checkpoint_work=40 * len(data.vertices))
    journal.flush()  # the base copy is written before the first step
    say("READY")

    def after(step: int) -> None:
        say(f"DONE {journal.records}")
        if step + 1 < STEPS:
            say(f"START {step + 1}")

    say("START 0")
    run(sculptor, seed, after)
    journal.flush()
    say("END")
    time.sleep(60)  # the test kills it


def main() -> None:
    import gogreen_core.files.journal  # noqa: F401  (imported once, before the forks)

    for line in sys.stdin:
        pid = os.fork()
        if pid == 0:
            try:
                session(line.split())
            finally:
                os._exit(0)
        os.waitpid(pid, 0)
        say(f"EXIT {pid}")


if __name__ == "__main__":
    main()
