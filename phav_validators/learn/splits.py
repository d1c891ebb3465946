"""Train/test splits: the paper's random 80/20, and splits that hold out whole groups
(human models, motions) so that no held-out model or motion is seen in training.

A clip's groups of a kind list its members, the one that decides its side first: for
``actor`` the protagonist, then the supporting person; for ``motion`` the base motion, then
the blended one. A clip is tested when its deciding members are held out, and trained on
only when none of its members is: a training clip never shows a held-out performer or
motion. A test clip whose other member (a partner) is a training clip's member too is
``mixed``: scored apart, and left out of the learnability verdict, which is on test clips
whose every performer (or motion) training never saw (``verdict_clips``). Background people
are no performers; with ``background: exclude`` a training clip that shows a held-out model
in the background is dropped too.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

import numpy as np

from phav_spec.errors import PhavUserError
from phav_spec.recipe_table import read_recipe_table
from phav_spec.seeding import seeded_rng
from phav_validators.learn.data import clip_groups


class Grouped(Protocol):
    """What a split reads of a clip: its key, label and groups (``data.Clip`` has them)."""

    key: str
    label: int
    groups: dict[str, tuple[str, ...]]


@dataclass(frozen=True)
class _Video:
    key: str
    label: int
    groups: dict[str, tuple[str, ...]]


#: What a split may hold out: ``actor`` (human models: protagonists and supporting people)
#: and ``motion`` (base and blended motions, chosen per action so every action keeps motions
#: on both sides).
HOLD_OUT = ("actor", "motion")
#: What a held-out-actor split does with training clips that show a held-out model among
#: the background people: ``keep`` them (counted in ``Split.background_seen``) or ``exclude`` them.
BACKGROUND = ("keep", "exclude")


@dataclass(frozen=True)
class Split:
    """Indices into a clip list; ``held_out`` names the groups only the test set has."""

    name: str
    train: list[int]
    test: list[int]
    dropped: int = 0  # clips on neither side (a held-out partner of a seen protagonist, …)
    held_out: dict[str, list[str]] = field(default_factory=dict)
    #: Test clips with a member seen in training (a held-out protagonist's seen partner).
    mixed: list[int] = field(default_factory=list)
    #: Training clips that show a held-out model among their background people (``keep``).
    background_seen: list[int] = field(default_factory=list)
    #: Training clips dropped because of it (``exclude``).
    background_dropped: int = 0


def _rng(seed: int) -> np.random.Generator:
    return seeded_rng(seed)


def random_split(n: int, *, test_fraction: float = 0.2, seed: int) -> Split:
    """A seeded random split of ``n`` clips, ``round(test_fraction · n)`` (≥ 1) of them tested."""
    if n < 2:
        raise PhavUserError(f"a split needs at least 2 clips, got {n}")
    k = min(n - 1, max(1, round(test_fraction * n)))
    order = _rng(seed).permutation(n)
    return Split("random", sorted(int(i) for i in order[k:]), sorted(int(i) for i in order[:k]))


def held_out_split(
    clips: Sequence[Grouped],
    hold: Sequence[str],
    *,
    test_fraction: float = 0.2,
    seed: int,
    background: str = "keep",
) -> Split:
    """Hold out about ``test_fraction`` of each kind in ``hold`` (the module's policy).

    Actors are drawn among the protagonists; motions per label among its clips' base
    motions (at least one of each label's motions stays in training, and one is tested
    where it has two or more that no other label needs to keep)."""
    unknown = [h for h in hold if h not in HOLD_OUT]
    if unknown or not hold:
        raise PhavUserError(f"can hold out {' and '.join(HOLD_OUT)}, got {list(hold)!r}", field="--split")
    if background not in BACKGROUND:
        raise PhavUserError(f"choose {' or '.join(BACKGROUND)}, got {background!r}", field="--learn-background")
    rng = _rng(seed)
    held: dict[str, set[str]] = {}
    if "actor" in hold:
        actors = sorted({_group(c, "actor")[0] for c in clips})
        if len(actors) < 2:
            raise PhavUserError(f"holding out actors needs at least 2, the data has {len(actors)}", field="--split")
        k = min(len(actors) - 1, max(1, round(test_fraction * len(actors))))
        held["actor"] = {actors[int(i)] for i in rng.permutation(len(actors))[:k]}
    if "motion" in hold:
        held["motion"] = _held_motions(clips, test_fraction, rng)
    train, test, dropped, seen_background, background_dropped = [], [], 0, [], 0
    for i, clip in enumerate(clips):
        deciding = [_group(clip, kind)[0] in held[kind] for kind in hold]
        touches = any(m in held[kind] for kind in hold for m in _group(clip, kind))
        if all(deciding):
            test.append(i)
        elif touches:
            dropped += 1
        elif "actor" in held and any(m in held["actor"] for m in clip.groups.get("background", ())):
            if background == "exclude":
                background_dropped += 1
            else:
                train.append(i)
                seen_background.append(i)
        else:
            train.append(i)
    if not train or not test:
        raise PhavUserError(f"holding out {'+'.join(hold)} leaves {len(train)} training and {len(test)} test clips",
                            field="--split")  # fmt: skip
    seen = {kind: {m for i in train for m in _group(clips[i], kind)} for kind in hold}
    mixed = [i for i in test if any(m in seen[kind] for kind in hold for m in _group(clips[i], kind)[1:])]
    return Split("held-out " + "+".join(hold), train, test, dropped, {k: sorted(v) for k, v in held.items()},
                 mixed, seen_background, background_dropped)  # fmt: skip


def verdict_clips(split: Split) -> tuple[list[int], bool]:
    """The test clips a verdict is on: those whose every member training never saw (the
    split's test less its ``mixed``), and False; where every test clip is mixed (a set of a
    few videos), all of them, and True, for the report to say so."""
    mixed = set(split.mixed)
    clean = [i for i in split.test if i not in mixed]
    return (clean, False) if clean else (list(split.test), bool(split.test))


def _held_motions(clips: Sequence[Grouped], test_fraction: float, rng: np.random.Generator) -> set[str]:
    """About ``test_fraction`` of each label's base motions, drawn per label, never the last
    one a label keeps: θ shares motions between actions (a walk on a line is a walk's motion
    too), and a motion held for one label is held for every label that shows it."""
    motions = {label: sorted({_group(c, "motion")[0] for c in clips if c.label == label})
               for label in sorted({c.label for c in clips})}  # fmt: skip
    held: set[str] = set()

    def may_hold(motion: str) -> bool:
        return all(any(m not in held and m != motion for m in ms) for ms in motions.values() if motion in ms)

    for ms in motions.values():
        if len(ms) < 2:
            continue
        k = min(len(ms) - 1, max(1, math.floor(test_fraction * len(ms) + 0.5)))
        for i in rng.permutation(len(ms)):
            if sum(m in held for m in ms) >= k:
                break
            if ms[int(i)] not in held and may_hold(ms[int(i)]):
                held.add(ms[int(i)])
    return held


def _group(clip: Grouped, kind: str) -> tuple[str, ...]:
    try:
        return clip.groups[kind]
    except KeyError:
        raise PhavUserError(f"clip {clip.key} has no {kind} group to hold out", field="--split") from None


def check_split_kind(kind: str) -> None:
    """Raise a PhavUserError unless ``kind`` is ``random`` or held-out groups (``actor+motion``)."""
    parts = kind.split("+")
    if kind != "random" and (not all(p in HOLD_OUT for p in parts) or len(set(parts)) != len(parts)):
        raise PhavUserError(f"expected random, actor, motion or actor+motion, got {kind!r}", field="--split")


def make_split(
    clips: Sequence[Grouped], kind: str, *, test_fraction: float = 0.2, seed: int, background: str = "keep"
) -> Split:
    """``random``, ``actor``, ``motion`` or ``actor+motion``; ``background`` as ``held_out_split``'s."""
    check_split_kind(kind)
    if kind == "random":
        return random_split(len(clips), test_fraction=test_fraction, seed=seed)
    return held_out_split(clips, kind.split("+"), test_fraction=test_fraction, seed=seed, background=background)


def dataset_split(
    root: str | Path, kind: str = "actor", *, seed: int, test_fraction: float = 0.2, background: str = "keep"
) -> tuple[list[str], list[str]]:
    """The training and test video ids of a dataset directory's ``kind`` split, from its
    recipes alone: the split ``phav train`` and the learnability check make for ``seed``
    (e.g. to give ``phav_spec.torchdata.PhavClips`` its ``videos``)."""
    videos = sorted((_Video(v, label, groups) for v, label, groups in clip_groups(read_recipe_table(
        Path(root) / "recipes.parquet"))), key=lambda c: c.key)  # fmt: skip
    split = make_split(videos, kind, test_fraction=test_fraction, seed=seed, background=background)
    return [videos[i].key for i in split.train], [videos[i].key for i in split.test]
