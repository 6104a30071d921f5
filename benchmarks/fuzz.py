"""The long fuzz run: every parser (the mesh readers, the session, preset and journal parsers,
the command line's arguments) on ≥ 100,000 mutated inputs each; the rule each input must keep
is in tests/helpers/fuzz_targets.py (load into a finite, in-range value, or be refused with a
ValueError naming the file or option; nothing else, no hang).

    nice python benchmarks/fuzz.py [--inputs 100000] [--seed 0] [--only NAME ...]

Prints, per parser: inputs, seconds, failures (and the first few failing inputs). Deterministic
for a given seed. Figures only; the short seeded run in the suite is
tests/core/interaction/test_fuzz_parsers.py.
"""

from __future__ import annotations

import argparse
import random
import signal
import sys
import tempfile
import time
from pathlib import Path
from types import FrameType

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from fuzz_targets import Target, check, mutate, reframed, targets

#: Seconds one input may take before it counts as a hang.
HANG_SECONDS = 20


class _Hang(Exception):
    pass


def _alarm(signum: int, frame: FrameType | None) -> None:
    raise _Hang


def run(target: Target, inputs: int, seed: int, folder: Path) -> tuple[float, list[str]]:
    rng = random.Random(f"{seed}-{target.name}")
    failures: list[str] = []
    start = time.perf_counter()
    for _ in range(inputs):
        data = rng.choice(target.seeds)
        data = (
            reframed(data, rng, target.seeds)
            if target.name == "journal" and rng.random() < 0.5
            else mutate(data, rng, target.seeds)
        )
        signal.setitimer(signal.ITIMER_REAL, HANG_SECONDS)
        try:
            problem = check(target, data, folder)
        except _Hang:
            problem = f"no answer within {HANG_SECONDS} s"
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
        if problem is not None:
            failures.append(f"{problem} <- {data[:300]!r}")
    return time.perf_counter() - start, failures


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--inputs", type=int, default=100_000, help="inputs per parser")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--only", nargs="*", help="parser names (default: all)")
    args = parser.parse_args()
    signal.signal(signal.SIGALRM, _alarm)
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        chosen = [t for t in targets(folder) if not args.only or t.name in args.only]
        print(f"{'parser':14s} {'inputs':>9s} {'seconds':>9s} {'failures':>9s}", flush=True)
        total = 0
        for target in chosen:
            seconds, failures = run(target, args.inputs, args.seed, folder)
            total += len(failures)
            print(
                f"{target.name:14s} {args.inputs:9,d} {seconds:9.1f} {len(failures):9d}", flush=True
            )
            for failure in failures[:5]:
                print(f"    {failure[:400]}", flush=True)
    print(f"failures in all: {total}")


if __name__ == "__main__":
    main()
