"""Crash recovery under SIGKILL: a process sculpts under a journal (strokes, pins, settings drags,
undos, redos; tests/helpers/journal_script.py) and is killed at 50 moments, some in the middle of a
journal write and of a checkpoint; every time, recovery must give back bit for bit the mesh,
pins and settings after the last operation that completed before the kill."""

from __future__ import annotations

import os
import queue
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import journal_script
import numpy as np

from gogreen_core import Sculptor
from gogreen_core.files.journal import Journal
from gogreen_core.files.recovery import RECOVERY_WORK, list_journals, recover

SCRIPT = Path(__file__).resolve().parents[2] / "helpers" / "journal_script.py"
KILLS = 50
SEEDS = 5
MODES = ("time", "record", "checkpoint")


def reference(seed: int, root: Path) -> dict[int, str]:
    """Journal records → fingerprint after them, from the same session run here."""
    data = journal_script.mesh()
    sculptor = Sculptor(data.vertices, data.faces)
    journal = Journal(sculptor, data, root=root, auto_checkpoint=False)
    states = {0: journal_script.fingerprint(sculptor)}

    def after(_step: int) -> None:
        states[journal.records] = journal_script.fingerprint(sculptor)

    journal_script.run(sculptor, seed, after)
    journal.close()
    return states


class Sessions:
    """The process that forks a sculpting session per kill (tests/helpers/journal_script.py), its
    output lines read on a thread."""

    def __init__(self) -> None:
        self.process = subprocess.Popen(
            [sys.executable, str(SCRIPT)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
        )
        self.lines: queue.Queue[str] = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        for line in self.process.stdout:
            self.lines.put(line.strip())
        self.lines.put("")

    def start(self, root: Path, seed: int, slow: bool) -> None:
        self.seen: list[str] = []
        self.process.stdin.write(f"{root} {seed} {'--slow' if slow else ''}\n")
        self.process.stdin.flush()
        self.pid = int(self.wait_for(lambda line: line.startswith("PID")).split()[1])

    def wait_for(self, wanted, timeout: float = 60.0) -> str:
        """The next line ``wanted(line)`` accepts, or one saying the session is gone."""
        deadline = time.monotonic() + timeout
        while True:
            line = self.lines.get(timeout=max(0.0, deadline - time.monotonic()))
            self.seen.append(line)
            if not line or line == f"EXIT {getattr(self, 'pid', '')}" or wanted(line):
                return line

    def kill(self) -> tuple[int, bool]:
        """SIGKILL the session, then read all it wrote: (records done, whether a step had
        started after the last one that finished)."""
        os.kill(self.pid, signal.SIGKILL)
        self.wait_for(lambda line: line == f"EXIT {self.pid}")
        done, started = 0, False
        for line in self.seen:
            if line.startswith("DONE"):
                done, started = int(line.split()[1]), False
            elif line.startswith("START"):
                started = True
        return done, started

    def close(self) -> None:
        self.process.stdin.close()
        self.process.wait(30)


def test_recovery_after_sigkill_gives_the_last_completed_operation_bit_for_bit(tmp_path):
    references = {seed: reference(seed, tmp_path / f"ref{seed}") for seed in range(SEEDS)}
    rng = np.random.default_rng(2024)
    torn_records = torn_checkpoints = 0
    outcomes: list[tuple] = []
    sessions = Sessions()
    try:
        for kill in range(KILLS):
            seed, mode = kill % SEEDS, MODES[kill % len(MODES)]
            root = tmp_path / f"kill{kill}"
            sessions.start(root, seed, slow=mode != "time")
            target = f"START {int(rng.integers(journal_script.STEPS))}"
            sessions.wait_for(lambda line, t=target: line in (t, "END"))
            if mode == "time":
                time.sleep(0.008 * rng.random())
            else:
                marker = "W" if mode == "record" else "C"
                if sessions.wait_for(lambda line, m=marker: line in (m, "END")) == marker:
                    time.sleep((0.001 if mode == "record" else 0.015) * rng.random())
            done, started = sessions.kill()
            journals = list_journals(root)
            assert len(journals) == 1 and not journals[0].in_use, (journals, sessions.seen)
            directory = journals[0].directory
            torn_checkpoints += any(directory.glob(".checkpoint-*.tmp"))
            # half from the newest usable checkpoint, half as deep as the budget allows
            recovery = recover(directory, budget=0 if kill % 2 else RECOVERY_WORK)
            try:
                torn_records += any("cut off" in note for note in recovery.notes)
                records = recovery.records
                outcomes.append((mode, done, records, recovery.start, recovery.notes))
                assert done <= records <= done + started, outcomes[-1]
                expected = references[seed][records]
                assert journal_script.fingerprint(recovery.sculptor) == expected, outcomes[-1]
                assert np.array_equal(recovery.mesh.vertices, recovery.sculptor.vertices)
            finally:
                recovery.release()
    finally:
        sessions.close()
    # the kills did land in the middle of writes (else this test could not fail there)
    assert torn_records >= 3, outcomes
    assert torn_checkpoints >= 2, outcomes
    assert any(start > 0 for _, _, _, start, _ in outcomes)  # checkpoints were used
