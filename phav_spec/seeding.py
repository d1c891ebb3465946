"""Every random stream of a dataset, derived one way: from (dataset seed, video index, named part…).

A dataset's randomness has one root, the dataset seed. Video ``i`` gets a 256-bit key,
``SeedSequence(dataset_seed, spawn_key=(i,))``; each named part of the graphical model
draws from its own PCG64 stream whose state is sha256(key ‖ part), so sampling 10 or 40,000
videos gives the same video ``i`` and adding a draw to one part never moves another's.
The recipe carries 32-bit *run-time seeds* hashed from the key by stage name (physics,
perturbation, render, background); a stage splits its seed into named streams with
``stream``. Checks and tools that draw outside a dataset (which videos to re-render, a
training shuffle) start from a user seed with ``seeded_rng``.

Every value here is part of the dataset's definition: the golden hashes under
``tests/golden`` pin them, and changing one bumps the recipe schema version.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable

import numpy as np

#: Seeds handed to run-time stages, each hashed from the video key and its name.
RUNTIME_SEEDS: tuple[str, ...] = ("physics", "perturbation", "render", "background")


def video_key(dataset_seed: int, index: int) -> bytes:
    """256 bits identifying video ``index`` of a dataset: SeedSequence(seed, spawn_key=(index,))."""
    if dataset_seed < 0 or index < 0:
        raise ValueError("dataset seed and video index must be non-negative")
    seq = np.random.SeedSequence(dataset_seed, spawn_key=(index,))
    return seq.generate_state(8, dtype=np.uint32).astype("<u4").tobytes()


def _part_state(key: bytes, part: str) -> dict:
    """PCG64 state of the stream ``part`` of a video: sha256(video key ‖ part) → state, inc."""
    digest = hashlib.sha256(key + b"/" + part.encode()).digest()
    return {
        "bit_generator": "PCG64",
        "state": {
            "state": int.from_bytes(digest[:16], "little"),
            "inc": int.from_bytes(digest[16:], "little") | 1,
        },
        "has_uint32": 0,
        "uinteger": 0,
    }


class PartStreams:
    """One reusable Generator per named part, re-pointed at each video's streams (cheap:
    sampling a recipe makes no new bit generator)."""

    def __init__(self, parts: Iterable[str]) -> None:
        self._bits = {p: np.random.PCG64(0) for p in parts}
        self._gens = {p: np.random.Generator(b) for p, b in self._bits.items()}
        self.key = b""

    def start(self, dataset_seed: int, index: int) -> None:
        """Point every part at video ``index`` of the dataset seeded ``dataset_seed``."""
        self.key = video_key(dataset_seed, index)

    def __getitem__(self, part: str) -> np.random.Generator:
        """The part's stream, rewound to its first draw for the current video. A name not
        given at construction gets its own stream on first use (``person/3``)."""
        if part not in self._bits:
            self._bits[part] = np.random.PCG64(0)
            self._gens[part] = np.random.Generator(self._bits[part])
        self._bits[part].state = _part_state(self.key, part)
        return self._gens[part]


def part_rng(dataset_seed: int, index: int, part: str) -> np.random.Generator:
    """A fresh Generator on the random stream of one named part of video ``index``."""
    streams = PartStreams((part,))
    streams.start(dataset_seed, index)
    return streams[part]


def named_seed(key: bytes, name: str) -> int:
    """A 32-bit seed hashed from the video key and a name (no draws)."""
    return int.from_bytes(hashlib.sha256(key + b"/seed:" + name.encode()).digest()[:4], "little")


def runtime_seeds(key: bytes) -> dict[str, int]:
    """32-bit seeds for the run-time stages, hashed from the video key by name (no draws)."""
    return {name: named_seed(key, name) for name in RUNTIME_SEEDS}


def stream(seed: int, name: str) -> np.random.Generator:
    """A run-time stage's named stream (``stream(recipe.seeds.physics, "car_hit")``): one
    independent generator per name, ``SeedSequence(seed, spawn_key=utf-8 bytes of name)``."""
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed, spawn_key=tuple(name.encode()))))


def seeded_rng(seed: int, *salt: int) -> np.random.Generator:
    """One generator straight from a seed: PCG64(seed), or PCG64([seed, *salt]) where ``salt``
    separates two uses of one seed. For a stage that draws a single stream from its run-time
    seed (rain) and for draws outside any dataset (``--seed`` of a check, a split, a shuffle)."""
    return np.random.Generator(np.random.PCG64([seed, *salt] if salt else seed))
