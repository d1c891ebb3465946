"""Train/test splits: the paper's random 80/20, and splits that hold out whole groups
(human models, base motions) so that the test set shares no actor or motion with training."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from phav_spec.errors import PhavUserError
from phav_spec.seeding import seeded_rng
from phav_validators.learn.data import Clip

#: What a split may hold out: ``actor`` (the protagonist's human model) and ``motion``
#: (the base motion, chosen per action so every action keeps motions on both sides).
HOLD_OUT = ("actor", "motion")


@dataclass(frozen=True)
class Split:
    """Indices into a clip list; ``held_out`` names the groups only the test set has."""

    name: str
    train: list[int]
    test: list[int]
    dropped: int = 0  # clips on neither side (a held-out actor with a training motion, …)
    held_out: dict[str, list[str]] = field(default_factory=dict)


def _rng(seed: int) -> np.random.Generator:
    return seeded_rng(seed)


def random_split(n: int, *, test_fraction: float = 0.2, seed: int) -> Split:
    """A seeded random split of ``n`` clips, ``round(test_fraction · n)`` (≥ 1) of them tested."""
    if n < 2:
        raise PhavUserError(f"a split needs at least 2 clips, got {n}")
    k = min(n - 1, max(1, round(test_fraction * n)))
    order = _rng(seed).permutation(n)
    return Split("random", sorted(int(i) for i in order[k:]), sorted(int(i) for i in order[:k]))


def held_out_split(clips: Sequence[Clip], hold: Sequence[str], *, test_fraction: float = 0.2, seed: int) -> Split:
    """Hold out about ``test_fraction`` of each kind in ``hold``: a clip is tested when all
    its groups are held out, trained on when none is, and dropped otherwise.

    Actors are drawn among all actors; motions per label (at least one of each label's
    motions stays on each side when it has two or more)."""
    unknown = [h for h in hold if h not in HOLD_OUT]
    if unknown or not hold:
        raise PhavUserError(f"can hold out {' and '.join(HOLD_OUT)}, got {list(hold)!r}", field="--split")
    rng = _rng(seed)
    held: dict[str, set[str]] = {}
    if "actor" in hold:
        actors = sorted({_group(c, "actor") for c in clips})
        if len(actors) < 2:
            raise PhavUserError(f"holding out actors needs at least 2, the data has {len(actors)}", field="--split")
        k = min(len(actors) - 1, max(1, round(test_fraction * len(actors))))
        held["actor"] = {actors[int(i)] for i in rng.permutation(len(actors))[:k]}
    if "motion" in hold:
        held["motion"] = set()
        for label in sorted({c.label for c in clips}):
            motions = sorted({_group(c, "motion") for c in clips if c.label == label})
            if len(motions) < 2:
                continue
            k = min(len(motions) - 1, max(1, math.floor(test_fraction * len(motions) + 0.5)))
            held["motion"] |= {motions[int(i)] for i in rng.permutation(len(motions))[:k]}
    train, test, dropped = [], [], 0
    for i, clip in enumerate(clips):
        inside = [_group(clip, kind) in held[kind] for kind in hold]
        if all(inside):
            test.append(i)
        elif not any(inside):
            train.append(i)
        else:
            dropped += 1
    if not train or not test:
        raise PhavUserError(f"holding out {'+'.join(hold)} leaves {len(train)} training and {len(test)} test clips",
                            field="--split")  # fmt: skip
    return Split("held-out " + "+".join(hold), train, test, dropped, {k: sorted(v) for k, v in held.items()})


def _group(clip: Clip, kind: str) -> str:
    try:
        return clip.groups[kind]
    except KeyError:
        raise PhavUserError(f"clip {clip.key} has no {kind} group to hold out", field="--split") from None


def check_split_kind(kind: str) -> None:
    """Raise a PhavUserError unless ``kind`` is ``random`` or held-out groups (``actor+motion``)."""
    parts = kind.split("+")
    if kind != "random" and (not all(p in HOLD_OUT for p in parts) or len(set(parts)) != len(parts)):
        raise PhavUserError(f"expected random, actor, motion or actor+motion, got {kind!r}", field="--split")


def make_split(clips: Sequence[Clip], kind: str, *, test_fraction: float = 0.2, seed: int) -> Split:
    """``random``, ``actor``, ``motion`` or ``actor+motion``."""
    check_split_kind(kind)
    if kind == "random":
        return random_split(len(clips), test_fraction=test_fraction, seed=seed)
    return held_out_split(clips, kind.split("+"), test_fraction=test_fraction, seed=seed)
