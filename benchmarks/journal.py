"""Benchmark of the crash-recovery journal (issue "Never lose work").

    python benchmarks/journal.py [--meshes DIR] [--strokes 1000] [--repeats 40] [--skip-big]

Prints medians (and the spread) of, on the default model and on the 1M-vertex mesh of
``benchmarks/scale.py`` (the shared ogre subdivided twice; skipped when ../shared is absent):

* the time the journal adds to each mouse event (serializing it) and to each stroke's end
  (joining the events, framing and writing the record), measured inside the journal's listener,
  and ``end_stroke`` with and without a journal (the same strokes, interleaved);
* the fsync that follows on the worker thread (append → on disk);
* a checkpoint: the copy of the state on the GUI thread (taken when idle) and its write on the
  worker thread, and the base copy of the mesh;
* journal bytes per stroke;

then, on the 1M-vertex mesh, the recovery time after ``--strokes`` strokes (checkpoints taken
as the app does when idle after each stroke) from the default budget, from the newest
checkpoint, and with the newest checkpoint lost; and the time to read a journal of 1,000
30-event strokes. Issue goals: ≤ 1 ms added per stroke end (1M vertices included), recovery
after 1,000 strokes on 1M vertices ≤ 3 s. Figures only, no assertions.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.files.journal import JOURNAL_FILE, Journal
from gogreen_core.files.recovery import read_journal, recover
from gogreen_core.mesh.mesh_io import MeshData
from gogreen_core.mesh.shapes import default_model, icosphere

EVENTS = 30


def spread(samples: list[float], unit: float = 1e3, name: str = "ms") -> str:
    """Median, 10th and 90th percentiles of ``samples`` (seconds) in ``name`` units."""
    ordered = sorted(samples)
    low, high = ordered[len(ordered) // 10], ordered[(9 * len(ordered)) // 10]
    return (
        f"{unit * statistics.median(samples):9.3f} {name} (p10 {unit * low:.3f}, "
        f"p90 {unit * high:.3f}, n={len(samples)})"
    )


class Timed:
    """Wraps a journal's log listener to time each call by kind."""

    def __init__(self, journal: Journal) -> None:
        self.times: dict[str, list[float]] = {"event": [], "append": []}
        self._journal = journal
        self._listener = journal._on_log
        journal.sculptor.subscribe(self)
        journal._unsubscribe()  # the timed wrapper replaces the journal's own subscription
        journal._unsubscribe = lambda: None

    def __call__(self, kind: str, item, length: int) -> None:
        if not self._journal.active:  # the strokes timed without a journal
            return
        start = time.perf_counter()
        self._listener(kind, item, length)
        self.times.setdefault(kind, []).append(time.perf_counter() - start)


def strokes(sculptor: Sculptor, count: int, events: int, radius: float, seed: int) -> list:
    """``count`` grab strokes of ``events`` mouse events at random places."""
    rng = np.random.default_rng(seed)
    vertices = sculptor.vertices
    step = 0.002 * sculptor.model_size
    out = []
    for _ in range(count):
        center = vertices[rng.integers(len(vertices))].copy()
        direction = rng.standard_normal(3)
        delta = step * direction / np.linalg.norm(direction)
        out.append(
            (
                Brush("grab", radius=radius),
                [BrushEvent(center + k * delta, delta) for k in range(events)],
            )
        )
    return out


def stroke_costs(mesh: MeshData, label: str, repeats: int, radius: float) -> None:
    """Per-event and per-stroke-end costs, fsync, checkpoint and base copy, bytes per stroke."""
    print(f"\n== {label}: {len(mesh.vertices):,} vertices, {EVENTS}-event grab strokes, r={radius}")
    with tempfile.TemporaryDirectory() as root:
        sculptor = Sculptor(mesh.vertices, mesh.faces)
        sculptor.apply_brush(*strokes(sculptor, 1, 2, radius, 0)[0])  # numba code loaded
        start = time.perf_counter()
        journal = Journal(sculptor, mesh, root=root, auto_checkpoint=False)
        started = time.perf_counter() - start
        journal.flush()
        base = next(journal.directory.glob("base-*.npz"))
        print(f"start of a journal (GUI thread: state copy, hash, header): {1e3 * started:8.1f} ms")
        print(f"base copy of the mesh (worker thread): {base.stat().st_size / 2**20:.1f} MB")
        timed = Timed(journal)
        with_journal, without, fsync = [], [], []
        plan = strokes(sculptor, 2 * repeats, EVENTS, radius, 1)
        size0 = (journal.directory / JOURNAL_FILE).stat().st_size
        for k, (brush, events) in enumerate(plan):
            journaled = k % 2 == 0
            if not journaled:
                journal._stopped = True  # the same sculptor, the journal silent
            sculptor.begin_stroke(brush)
            for event in events:
                sculptor.stroke_event(event)
            start = time.perf_counter()
            sculptor.end_stroke()
            (with_journal if journaled else without).append(time.perf_counter() - start)
            journal._stopped = False
            if journaled:
                written = time.perf_counter()
                while journal.durable < journal.records:
                    time.sleep(0.0001)
                fsync.append(time.perf_counter() - written)
        size = (journal.directory / JOURNAL_FILE).stat().st_size - size0
        event, append = (spread(timed.times[k], 1e6, "us") for k in ("event", "append"))
        print(f"journal, per mouse event (serialize):         {event}")
        print(f"journal, per stroke end (join, frame, write): {append}")
        print(f"end_stroke with the journal:                  {spread(with_journal)}")
        print(f"end_stroke without it:                        {spread(without)}")
        print(f"fsync after the append (worker thread):       {spread(fsync)}")
        print(f"journal bytes per {EVENTS}-event stroke:             {size / repeats:9.0f}")
        copies, writes = [], []
        for _ in range(min(repeats, 10)):
            start = time.perf_counter()
            journal.checkpoint()
            copies.append(time.perf_counter() - start)
            start = time.perf_counter()
            journal.flush()
            writes.append(time.perf_counter() - start)
        checkpoint = max(
            journal.directory.glob("checkpoint-*.bin"), key=lambda p: p.stat().st_mtime
        )
        print(f"checkpoint, copy on the GUI thread (idle):    {spread(copies)}")
        print(f"checkpoint, write on the worker thread:       {spread(writes)}")
        print(f"checkpoint size: {checkpoint.stat().st_size / 2**20:.1f} MB")
        journal.close()


def recovery_after_strokes(mesh: MeshData, count: int, radius: float) -> None:
    """Recovery time after ``count`` strokes, checkpoints taken as the app's idle timer does."""
    print(f"\n== recovery after {count:,} strokes ({3} events each, r={radius}) on "
          f"{len(mesh.vertices):,} vertices")  # fmt: skip
    with tempfile.TemporaryDirectory() as root:
        sculptor = Sculptor(mesh.vertices, mesh.faces)
        journal = Journal(sculptor, mesh, root=root, auto_checkpoint=False)
        start = time.perf_counter()
        for k, (brush, events) in enumerate(strokes(sculptor, count, 3, radius, 2)):
            sculptor.apply_brush(brush, events)
            journal.maybe_checkpoint()  # the app: when idle after the stroke
            if k % 100 == 99:
                print(f"  {k + 1} strokes, {time.perf_counter() - start:.0f} s", flush=True)
        journal.flush()
        directory = journal.directory
        journal.close(remove=False)  # as a crash leaves it
        size = sum(p.stat().st_size for p in directory.iterdir()) / 2**20
        records = (directory / JOURNAL_FILE).stat().st_size / 1024
        print(f"journal folder: {size:.0f} MB, of which {records:.0f} kB of records")
        for label, options in (
            ("default budget", {}),
            ("newest checkpoint", {"budget": 0}),
        ):
            seconds = []
            for _ in range(3):
                recovery = recover(directory, **options)
                seconds.append(recovery.seconds)
                assert np.array_equal(recovery.sculptor.vertices, sculptor.vertices)
                detail = f"start after record {recovery.start}, {recovery.replayed} replayed"
                recovery.release()
            print(f"recovery, {label:<18}: {spread(seconds, 1, 's')}  ({detail})")
        newest = max(directory.glob("checkpoint-*.bin"), key=lambda p: int(p.stem.split("-")[1]))
        newest.unlink()
        recovery = recover(directory)
        print(
            f"recovery, newest checkpoint lost: {recovery.seconds:.2f} s (start after record "
            f"{recovery.start}, {recovery.replayed} replayed)"
        )
        assert np.array_equal(recovery.sculptor.vertices, sculptor.vertices)
        recovery.release()


def reading(count: int) -> None:
    """Time to read (and check) a journal of ``count`` 30-event strokes."""
    vertices, faces = icosphere(2)
    with tempfile.TemporaryDirectory() as root:
        sculptor = Sculptor(vertices, faces)
        journal = Journal(sculptor, MeshData(vertices, faces), root=root, auto_checkpoint=False)
        for brush, events in strokes(sculptor, count, EVENTS, 0.1, 3):
            sculptor.apply_brush(brush, events)
        journal.flush()
        size = (journal.directory / JOURNAL_FILE).stat().st_size
        seconds = []
        for _ in range(5):
            start = time.perf_counter()
            read_journal(journal.directory)
            seconds.append(time.perf_counter() - start)
        print(f"\nreading a journal of {count:,} {EVENTS}-event strokes ({size / 2**20:.1f} MB): "
              f"{spread(seconds, 1, 's')}")  # fmt: skip
        journal.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument(
        "--meshes", default=str(Path(__file__).resolve().parents[2] / "shared/meshes")
    )
    parser.add_argument("--strokes", type=int, default=1000)
    parser.add_argument("--repeats", type=int, default=40)
    parser.add_argument("--skip-big", action="store_true", help="no 1M-vertex mesh")
    args = parser.parse_args()

    vertices, faces = default_model()
    stroke_costs(MeshData(vertices, faces), "default model", args.repeats, 0.1)
    reading(1000)
    ogre = Path(args.meshes) / "ogre.obj"
    if args.skip_big or not ogre.exists():
        print(f"\n(no 1M-vertex mesh: {ogre} absent or --skip-big)")
        return
    from scale import million_vertex_mesh

    vertices, faces, name = million_vertex_mesh(Path(args.meshes))
    big = MeshData(vertices, faces)
    stroke_costs(big, name, max(10, args.repeats // 4), 0.03)
    recovery_after_strokes(big, args.strokes, 0.03)


if __name__ == "__main__":
    main()
