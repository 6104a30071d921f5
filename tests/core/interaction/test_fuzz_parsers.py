"""Fuzzing in the suite (issue 37 item 5): every parser on generated and mutated inputs, seeded
and short (benchmarks/fuzz.py is the long run). The rule and the targets are in
fuzz_targets.py: an input loads into a finite, in-range value or is refused with a ValueError
naming the file (or option); no other exception.

Hypothesis generates the edits (which seed, which mutations, raw bytes) and, when an input
breaks the rule, shrinks it to a small one before reporting it; ``derandomize=True`` makes the
run the same every time."""

from __future__ import annotations

import random

import pytest
from fuzz_targets import Target, check, mutate, reframed, targets
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

FUZZ_SETTINGS = settings(
    max_examples=60,
    derandomize=True,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


@pytest.fixture(scope="module")
def all_targets(tmp_path_factory) -> dict[str, Target]:
    return {t.name: t for t in targets(tmp_path_factory.mktemp("fuzz"))}


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz-scratch")


NAMES = ["obj", "ply-ascii", "ply-binary", "stl-ascii", "stl-binary", "off", "session",
         "preset", "journal", "command line"]  # fmt: skip


@pytest.mark.parametrize("name", NAMES)
def test_mutated_inputs_load_or_are_refused_cleanly(all_targets, scratch, name):
    target = all_targets[name]

    @FUZZ_SETTINGS
    @given(
        seed=st.integers(0, len(target.seeds) - 1),
        rounds=st.integers(1, 3),
        rng=st.randoms(use_true_random=False),
        reframe=st.booleans(),
    )
    def mutated(seed: int, rounds: int, rng: random.Random, reframe: bool) -> None:
        data = target.seeds[seed]
        for _ in range(rounds):
            if name == "journal" and reframe:
                data = reframed(data, rng, target.seeds)
            else:
                data = mutate(data, rng, target.seeds)
        assert check(target, data, scratch) is None, check(target, data, scratch)

    mutated()


@pytest.mark.parametrize("name", NAMES)
def test_generated_inputs_load_or_are_refused_cleanly(all_targets, scratch, name):
    """Inputs that owe nothing to the seeds: raw bytes, and a seed's head followed by them."""
    target = all_targets[name]

    @FUZZ_SETTINGS
    @given(st.binary(max_size=400), st.integers(0, 2000), st.integers(0, len(target.seeds) - 1))
    def generated(tail: bytes, cut: int, seed: int) -> None:
        for data in (tail, target.seeds[seed][:cut] + tail):
            problem = check(target, data, scratch)
            assert problem is None, problem

    generated()


def test_the_rule_catches_what_it_should(all_targets, scratch):
    """The check is not blind: another exception, or a value out of range, is a failure."""
    from fuzz_targets import Failure

    def crash(data, folder):
        raise IndexError("boom")

    def bad(data, folder):
        raise Failure("out of range")

    def anonymous(data, folder):
        raise ValueError("something is wrong")

    for run in (crash, bad, anonymous):
        assert check(Target("obj", [b""], run, ("fuzz.obj",)), b"", scratch) is not None
