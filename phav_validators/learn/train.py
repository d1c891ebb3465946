"""Training and testing a TSN stream, alone on one source or Cool-TSN on mixed sources.

Mini-batches take a fixed number of clips from each source (the paper: blocks of 32 with
10 virtual and 22 real); each clip gives K snippets, one per uniform segment, at a random
offset while training and at segment centres when testing. The loss is the multi-task loss
of ``model.multitask_loss``. A checkpoint is written atomically after every epoch, with
the optimiser and random states, so an interrupted run resumes to the same weights an
uninterrupted one reaches. Results are deterministic for a given seed and thread count on
a CPU; on a GPU cuDNN is held to its deterministic algorithms, which has not been measured
bit-exact.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import math
import os
import re
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write
from phav_spec.host import cpu_fields
from phav_spec.seeding import seeded_rng
from phav_validators.learn.config import Architecture, in_channels, require_torch
from phav_validators.learn.data import Clip

#: TSN's gradient-norm clips (RGB 40, flow 20) and the fusion weights of its two streams.
CLIP_GRAD = {"rgb": 40.0, "flow": 20.0}
FUSION_WEIGHTS = {"rgb": 1.0, "flow": 1.5}
#: Flow is clipped at ±20 px of a 340-px-wide frame (TSN's bound), scaled to the stored width.
FLOW_BOUND_PX = 20.0
PRECISIONS = ("fp32", "bf16")
#: The devices training runs on: the CPU or a CUDA GPU (``cuda``, ``cuda:N``). torch names
#: more (``mps``, ``xpu``, …) that this code neither supports nor tests.
_DEVICE = re.compile(r"cpu|cuda(:\d+)?")
_RGB_MEAN, _RGB_STD = 0.45, 0.225
#: map(function, items) → list, as a batch's clips are cut (``cutting``).
Mapper = Callable[[Callable[[Any], Any], Sequence[Any]], list[Any]]
#: The ``TrainConfig`` settings of the RGB stream alone, back at their defaults for flow.
_RGB_ONLY = ("rgb_frames", "rgb_diff", "diff_gain", "distill")


@dataclass(frozen=True)
class TrainConfig:
    """How one stream is trained; everything that changes the weights is here."""

    stream: str = "flow"
    segments: int = 3
    test_segments: int = 5
    flow_frames: int = 5
    #: RGB frames stacked per snippet (1: TSN's single frame; more let the stream see motion).
    rgb_frames: int = 1
    #: Stacked RGB frames enter as the first frame and the differences between consecutive
    #: frames (a linear change of the same pixels, TSN's RGB difference beside appearance),
    #: so motion is not a small residue the first layer must learn to subtract.
    rgb_diff: bool = False
    #: Factor on the RGB differences (``rgb_diff``): a difference is several times smaller
    #: than a frame, so at 1 the first frame's appearance dominates the first layer from its
    #: start (docs/experiments/learnability.md, "The defaults and why").
    diff_gain: float = 1.0
    crop: float = 0.875  # side of the random training crop (centre crop when testing), share of the frame
    #: TSN's multi-scale cropping while training: each clip's crop takes a height and a width
    #: from (1, 7/8, 3/4, 2/3) of the frame's, at most one step apart, anywhere in the frame,
    #: resized to the ``crop`` the network sees (flow vectors scaled with it, so a magnified
    #: crop's flow may pass the ±4 input bound by up to a third): actors of every size in
    #: every place. Testing keeps the centre crop.
    scale_jitter: bool = False
    widths: tuple[int, ...] = Architecture.widths
    dropout: float = 0.3
    stem_pool: bool = Architecture.stem_pool
    #: RGB stream with a flow teacher (``train(teacher=…)``): weight of matching the
    #: teacher's pooled features on the same snippets (MARS, Crasto et al. 2019), so the
    #: RGB stream learns the motion features flow has. Training only: it is tested alone.
    distill: float = 0.0
    epochs: int = 80
    #: Epochs of the RGB stream when it differs from the flow stream's (None: ``epochs``),
    #: so a distilled RGB stream can take a smaller share of a time budget.
    rgb_epochs: int | None = None
    #: Clips per mini-batch from each source, e.g. {"virtual": 10, "real": 22}.
    mix: tuple[tuple[str, int], ...] = (("virtual", 32),)
    #: TSN's SGD: peak learning rate (cosine decay), momentum and weight decay.
    lr: float = 0.05
    momentum: float = 0.9
    weight_decay: float = 5e-4
    seed: int = 0
    threads: int = 1
    #: Arithmetic of the forward pass: ``fp32``, or ``bf16`` autocast (convolutions in
    #: bfloat16, losses and weights in float32), faster where the device computes bfloat16
    #: natively (``default_precision``).
    precision: str = "fp32"

    def __post_init__(self) -> None:
        in_channels(self.stream, self.flow_frames)  # raises on an unknown stream
        for name, value in (
            ("segments", self.segments),
            ("test_segments", self.test_segments),
            ("flow_frames", self.flow_frames),
            ("rgb_frames", self.rgb_frames),
            ("epochs", self.epochs),
            ("rgb_epochs", self.rgb_epochs if self.rgb_epochs is not None else 1),
            ("threads", self.threads),
        ):
            if value < 1:
                raise PhavUserError(f"must be at least 1, got {value}", field=f"--{name.replace('_', '-')}")
        if not 0.2 <= self.crop <= 1.0:
            raise PhavUserError(f"must be in [0.2, 1], got {self.crop}", field="--crop")
        if not self.mix or any(n < 1 for _, n in self.mix):
            raise PhavUserError(f"every source needs at least one clip per batch, got {dict(self.mix)}", field="--mix")
        if self.precision not in PRECISIONS:
            raise PhavUserError(f"choose {' or '.join(PRECISIONS)}, got {self.precision!r}", field="--precision")
        for name, value in (("lr", self.lr), ("diff_gain", self.diff_gain), ("distill", self.distill)):
            if not math.isfinite(value):  # inf passed the checks below and diverged as --lr
                raise PhavUserError(f"must be finite, got {value}", field=f"--{name.replace('_', '-')}")
        if not self.lr > 0:
            raise PhavUserError(f"must be positive, got {self.lr}", field="--lr")
        if self.distill < 0 or (self.distill > 0 and self.stream != "rgb"):
            raise PhavUserError(f"needs the rgb stream and a non-negative weight, got {self.distill}",
                                field="--distill")  # fmt: skip
        if not self.diff_gain > 0:
            raise PhavUserError(f"must be positive, got {self.diff_gain}", field="--diff-gain")
        self.arch  # noqa: B018 - the network's options (--widths, --dropout) checked now, not after the data is read
        if self.rgb_diff and (self.stream != "rgb" or self.rgb_frames < 2):
            raise PhavUserError("needs the rgb stream with --rgb-frames of 2 or more", field="--rgb-diff")

    def for_stream(self, stream: str) -> TrainConfig:
        """This config for ``stream``: the RGB stream takes its own epochs (``rgb_epochs``);
        the RGB-only settings (``_RGB_ONLY``: stacked frames, differences, distillation)
        return to their defaults for the flow stream."""
        if stream == "rgb":
            epochs = self.rgb_epochs if self.rgb_epochs is not None else self.epochs
            return replace(self, stream=stream, epochs=epochs, rgb_epochs=None)
        return replace(self, stream=stream, rgb_epochs=None, **{f: getattr(TrainConfig, f) for f in _RGB_ONLY})

    @property
    def arch(self) -> Architecture:
        return Architecture(widths=self.widths, dropout=self.dropout, stem_pool=self.stem_pool)

    @property
    def batch(self) -> int:
        return sum(n for _, n in self.mix)

    @property
    def sources(self) -> list[str]:
        return [name for name, _ in self.mix]

    def to_json(self) -> dict[str, Any]:
        return json.loads(json.dumps(asdict(self)))

    def changed(self) -> dict[str, Any]:
        """``to_json`` without the settings at their defaults."""
        defaults = TrainConfig().to_json()
        return {k: v for k, v in self.to_json().items() if v != defaults[k]}


@dataclass
class Epoch:
    """One epoch's record: mean loss per source, training accuracy, seconds."""

    epoch: int
    losses: dict[str, float]
    train_accuracy: float
    seconds: float


@dataclass
class Teacher:
    """A trained flow stream whose pooled snippet features an RGB stream learns to match
    (``TrainConfig.distill``); it sees the same clips, starts, crops and flips."""

    model: Any  # phav_validators.learn.model.TSN of the flow stream
    config: TrainConfig

    def loss(self, features: Any, targets: Sequence[Mapping[str, np.ndarray]]) -> Any:
        """Mean squared distance of the student's features to the teacher's (no gradient to the teacher)."""
        import torch  # optional extra phav[train]: only training needs torch

        x = torch.from_numpy(np.stack([t["teacher"] for t in targets])).to(features.device)
        self.model.eval()
        with torch.no_grad(), autocast(self.config, features.device):
            _, more = self.model(x, extras=True)
        return torch.nn.functional.mse_loss(features, more["features"].float())

    def digest(self) -> str:
        """A hash of the teacher's weights (a checkpoint resumes only with the same teacher)."""
        h = hashlib.sha256()
        for name, tensor in sorted(self.model.state_dict().items()):
            h.update(name.encode())
            h.update(tensor.detach().cpu().numpy().tobytes())
        return h.hexdigest()


def stream_order(streams: Sequence[str], base: TrainConfig) -> list[str]:
    """The order ``streams`` train in: the flow stream first when the RGB stream learns
    from it (``distill``), which needs both; otherwise as given."""
    if base.distill > 0 and "rgb" in streams:
        if "flow" not in streams:
            raise PhavUserError("the RGB stream distils from the flow stream: train both (--streams rgb,flow)",
                                field="--distill")  # fmt: skip
        return sorted(streams, key=lambda s: s != "flow")
    return list(streams)


def stream_configs(streams: Sequence[str], base: TrainConfig) -> dict[str, TrainConfig]:
    """Each of ``streams``' own settings (``for_stream``), in the order they train
    (``stream_order``): a setting a stream refuses raises here, before any data is read."""
    configs = {stream: base.for_stream(stream) for stream in streams}
    return {stream: configs[stream] for stream in stream_order(streams, base)}


def teacher_of(stream: str, result: TrainResult, base: TrainConfig) -> Teacher | None:
    """The teacher the next stream in ``stream_order`` trains with, given the one just
    trained: the flow stream when the RGB stream (then the next, and last) distils from it."""
    return Teacher(result.model, result.config) if stream == "flow" and base.distill > 0 else None


#: Where ``phav train``, the learnability check and the training bench start: the flow
#: stream as TSN's for 160 epochs, with TSN's multi-scale crops; the RGB stream on five
#: frames entered as the first and four differences at twelve times their scale, matching
#: the flow stream's features (weight 20), for 50 epochs; both with a max-pool after the
#: stem on a CPU (``default_stem_pool``), where time binds and the pooled stem buys the
#: epochs. Each choice won against its alternatives in docs/experiments/learnability.md,
#: "The defaults and why" and "Augmentation".
RECOMMENDED = TrainConfig(stream="rgb", rgb_frames=5, rgb_diff=True, diff_gain=12.0, distill=20.0, epochs=160,
                          rgb_epochs=50, scale_jitter=True, stem_pool=True)  # fmt: skip
#: The RGB stream's default epochs against the flow stream's, as the CLIs' help says it.
RGB_EPOCH_SHARE = f"{RECOMMENDED.rgb_epochs} per {RECOMMENDED.epochs}"


def recommended_config(streams: Sequence[str], *, device: str = "cpu", **settings: Any) -> TrainConfig:
    """``RECOMMENDED`` for training ``streams`` on ``device`` (its threads, precision and stem), with
    ``settings`` changed; other ``epochs`` scale the RGB stream's with them unless
    ``rgb_epochs`` is given, and RGB differences need 2 or more frames unless ``rgb_diff``
    is given. Without both streams the RGB stream has no flow stream to learn from, so it
    trains without distillation; without the RGB stream its settings are moot, and without
    differences so is their gain (kept at 1, so the settings do not claim one)."""
    base = replace(
        RECOMMENDED, threads=default_threads(), precision=default_precision(device), stem_pool=default_stem_pool(device)
    )
    if "rgb" not in streams:
        base = base.for_stream(streams[0])
    elif "flow" not in streams:
        base = replace(base, distill=0.0)
    if settings.get("rgb_epochs") is None and "epochs" in settings:
        share = RECOMMENDED.rgb_epochs / RECOMMENDED.epochs
        settings = {**settings, "rgb_epochs": max(1, round(settings["epochs"] * share))}
    if settings.get("rgb_diff") is None:
        settings = {**settings, "rgb_diff": base.rgb_diff and settings.get("rgb_frames", base.rgb_frames) >= 2}
    if not settings["rgb_diff"]:
        settings = {**settings, "diff_gain": TrainConfig.diff_gain}
    config = replace(base, **settings)
    # Settings given for the RGB stream (a CLI passes them all) are moot without it.
    return config if "rgb" in streams else config.for_stream(streams[0])


@dataclass
class TrainResult:
    """The trained model and what training did."""

    model: Any  # phav_validators.learn.model.TSN
    config: TrainConfig
    history: list[Epoch] = field(default_factory=list)
    seconds: float = 0.0
    stopped_on_time: bool = False
    resumed_from: int = 0  # epochs already done when this run started


# --- snippets ------------------------------------------------------------------------------


def snippet_starts(n_frames: int, segments: int, length: int, *, rng: np.random.Generator | None) -> list[int]:
    """First frame of each segment's snippet of ``length`` frames: a random offset in the
    segment with ``rng``, its centre without. Clips shorter than a snippet start at 0."""
    span = max(n_frames - length + 1, 1)
    step = span / segments
    if rng is None:
        return [min(span - 1, int(step * (k + 0.5))) for k in range(segments)]
    return [min(span - 1, int(step * k + rng.random() * step)) for k in range(segments)]


def crop_box(shape: tuple[int, int], crop: float) -> tuple[int, int]:
    """(height, width) of the crop of a (height, width) frame."""
    return max(1, round(shape[0] * crop)), max(1, round(shape[1] * crop))


#: TSN's crop scales (share of the frame's height or width) for ``scale_jitter``, and the
#: (height, width) scale pairs it draws from: at most one step apart.
JITTER_SCALES = (1.0, 0.875, 0.75, 0.66)
_JITTER_PAIRS = [(a, b) for i, a in enumerate(JITTER_SCALES) for j, b in enumerate(JITTER_SCALES) if abs(i - j) <= 1]
#: The most channels OpenCV resizes in one call.
_CV_CHANNELS = 128


def jitter_box(shape: tuple[int, int], rng: np.random.Generator) -> tuple[int, int]:
    """(height, width) of a multi-scale training crop of a (height, width) frame."""
    sy, sx = _JITTER_PAIRS[int(rng.integers(len(_JITTER_PAIRS)))]
    return crop_box(shape, sy)[0], crop_box(shape, sx)[1]


def resize_snippets(x: np.ndarray, size: tuple[int, int], *, kind: str) -> np.ndarray:
    """Snippets (K, C, h, w) of ``kind`` ``rgb`` or ``flow`` at ``size`` (height, width),
    bilinear; flow's u (even channels) and v (odd) scaled with the frame."""
    h, w = x.shape[-2:]
    if (h, w) == tuple(size):
        return x
    planes = x.reshape(-1, h, w).transpose(1, 2, 0)
    out = np.concatenate([cv2.resize(np.ascontiguousarray(planes[..., i : i + _CV_CHANNELS]), (size[1], size[0]),
                                     interpolation=cv2.INTER_LINEAR).reshape(size[0], size[1], -1)
                          for i in range(0, planes.shape[-1], _CV_CHANNELS)], axis=-1)  # fmt: skip
    out = out.transpose(2, 0, 1).reshape(*x.shape[:-2], *size)  # a view of the fresh array
    if kind == "flow":
        out[:, 0::2] *= size[1] / w
        out[:, 1::2] *= size[0] / h
    return out


def snippets(
    clip: Clip, config: TrainConfig, *, rng: np.random.Generator | None, segments: int | None = None
) -> np.ndarray:
    """One clip's input (K, C, h, w) float32: K snippets, cropped and normalised; with ``rng``
    a random crop and horizontal flip (flow's u negated), else the centre crop."""
    return snippets_and_targets(clip, config, rng=rng, segments=segments)[0]


@dataclass(frozen=True)
class Cut:
    """Where one clip's snippets are cut: the snippets' first frames, the crop's (height,
    width), its top-left corner and the flip. Drawn from the random state in one fixed order
    (``draw_cut``), so cutting a batch's clips in threads gives the arrays that cutting them
    one after another gives."""

    starts: tuple[int, ...]
    box: tuple[int, int]
    corner: tuple[int, int]
    flip: bool = False


def _snippet_length(config: TrainConfig) -> int:
    """Frames in one snippet of the config's stream."""
    return config.rgb_frames if config.stream == "rgb" else config.flow_frames


def snippet_frames(starts: Sequence[int], n_frames: int, length: int) -> np.ndarray:
    """(K, length) indices of the frames of the snippets starting at ``starts``, the clip's
    last frame repeated where a snippet runs past its end."""
    return np.minimum(np.add.outer(np.asarray(starts), np.arange(length)), n_frames - 1)


def draw_cut(clip: Clip, config: TrainConfig, *, rng: np.random.Generator | None, segments: int | None = None) -> Cut:
    """Where ``clip``'s K snippets are cut: with ``rng`` random offsets in their segments, a
    random crop (multi-scale with ``scale_jitter``) and flip; without, segment centres and
    the centre crop."""
    k = segments if segments is not None else config.segments
    starts = snippet_starts(clip.n_frames, k, _snippet_length(config), rng=rng)
    h, w = clip.rgb.shape[1:3]
    ch, cw = crop_box((h, w), config.crop)
    if config.scale_jitter and rng is not None:
        ch, cw = jitter_box((h, w), rng)
    if rng is None:
        return Cut(tuple(starts), (ch, cw), ((h - ch) // 2, (w - cw) // 2))
    corner = int(rng.integers(0, h - ch + 1)), int(rng.integers(0, w - cw + 1))
    return Cut(tuple(starts), (ch, cw), corner, flip=bool(rng.random() < 0.5))


def snippets_and_targets(
    clip: Clip,
    config: TrainConfig,
    *,
    rng: np.random.Generator | None,
    segments: int | None = None,
    teacher: TrainConfig | None = None,
) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """``snippets`` and the targets of a flow teacher under the same crop and flip:
    ``cut_clip`` at ``draw_cut``'s place."""
    where = draw_cut(clip, config, rng=rng, segments=segments)
    return cut_clip(clip, config, where, teacher=teacher)


def cut_clip(
    clip: Clip, config: TrainConfig, where: Cut, *, teacher: TrainConfig | None = None
) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """One clip's snippets (K, C, h, w) float32, cropped at ``where``, resized to the crop the
    network sees and normalised; given a flow teacher's config, its target ``teacher``: the
    flow snippets that teacher sees from the same starts under the same crop and flip."""
    k = len(where.starts)
    length = _snippet_length(config)
    frames = snippet_frames(where.starts, clip.n_frames, length)
    seen = crop_box(clip.rgb.shape[1:3], config.crop)
    (y0, x0), (ch, cw) = where.corner, where.box
    window = np.s_[y0 : y0 + ch, x0 : x0 + cw]
    out: dict[str, np.ndarray] = {}
    if config.stream == "rgb":
        x = clip.rgb[frames][:, :, window[0], window[1]].astype(np.float32)  # (K, L, h, w, 3)
        x = (x / 255.0 - _RGB_MEAN) / _RGB_STD
        if config.rgb_diff:
            x[:, 1:] = np.diff(x, axis=1) * config.diff_gain
        x = x.transpose(0, 1, 4, 2, 3).reshape(k, 3 * length, ch, cw)  # r0, g0, b0, r1, …
    else:
        x = _flow_input(clip, frames, window)
    if teacher is not None:
        span = snippet_frames(where.starts, clip.n_frames, teacher.flow_frames)
        out["teacher"] = resize_snippets(_flow_input(clip, span, window), seen, kind="flow")
    x = resize_snippets(x, seen, kind=config.stream)
    if where.flip:
        x = _flip(x, flow=config.stream == "flow")
        out = {name: _flip(t, flow=True) for name, t in out.items()}
    return np.ascontiguousarray(x), {name: np.ascontiguousarray(t) for name, t in out.items()}


def _flow_input(clip: Clip, frames: np.ndarray, window: tuple[slice, slice]) -> np.ndarray:
    """Flow frames (K, L) of ``clip`` in ``window`` → (K, 2L, h, w): each whole frame's median
    vector subtracted, clipped at TSN's bound and scaled to ±4. The median is mostly the
    camera's motion, which PHAV's following cameras add to every pixel: subtracted, it is not
    a signal the network must learn to ignore (docs/experiments/learnability.md, "Which flow")."""
    k, length = frames.shape
    bound = FLOW_BOUND_PX * clip.flow.shape[2] / 340.0
    x = clip.flow[frames][:, :, window[0], window[1]].astype(np.float32)  # (K, L, h, w, 2)
    ch, cw = x.shape[2:4]
    x -= clip.flow_median[frames][:, :, None, None, :]
    x = np.clip(x, -bound, bound) * (4.0 / bound)
    return x.transpose(0, 1, 4, 2, 3).reshape(k, 2 * length, ch, cw)  # u0, v0, u1, v1, …


def _flip(x: np.ndarray, *, flow: bool) -> np.ndarray:
    """Mirror snippets left–right; flow's u components (even channels) change sign."""
    x = x[..., ::-1]
    if flow:
        x = x.copy()
        x[:, 0::2] *= -1.0
    return x


# --- mini-batches ---------------------------------------------------------------------------


class MixedBatches:
    """Endless mini-batches of (source, clip index) with a fixed count per source.

    Each source is drawn without replacement from its own shuffled order, reshuffled when
    used up, so every batch holds every source in the configured ratio."""

    def __init__(self, pools: Mapping[str, Sequence[int]], mix: Sequence[tuple[str, int]], *, rng: np.random.Generator):
        for name, _ in mix:
            if not pools.get(name):
                raise PhavUserError(f"source {name!r} has no training clips", field="--mix")
        self._pools = {name: list(pools[name]) for name, _ in mix}
        self._mix = list(mix)
        self._rng = rng
        self._order: dict[str, list[int]] = {name: [] for name, _ in mix}

    def state(self) -> dict[str, list[int]]:
        """What is left of each source's current pass (checkpointed with the random state)."""
        return {name: list(order) for name, order in self._order.items()}

    def load_state(self, state: Mapping[str, Sequence[int]]) -> None:
        self._order = {name: list(state.get(name, ())) for name, _ in self._mix}

    def next(self) -> list[tuple[str, int]]:
        batch = []
        for name, count in self._mix:
            for _ in range(count):
                if not self._order[name]:
                    pool = self._pools[name]
                    self._order[name] = [pool[int(i)] for i in self._rng.permutation(len(pool))]
                batch.append((name, self._order[name].pop()))
        return batch


# --- training -------------------------------------------------------------------------------


def _fingerprint(
    config: TrainConfig, data: Mapping[str, Sequence[Clip]], heads: Mapping[str, int], init: str | Path | None
) -> str:
    """What a checkpoint must agree on to be resumed: the config, heads, start and training
    clips. Settings at their defaults are left out, so a setting added in a later version,
    or one removed that was left at its default, does not orphan a checkpoint made before it."""
    h = hashlib.sha256(json.dumps(config.changed(), sort_keys=True).encode())
    h.update(json.dumps([dict(sorted(heads.items())), None if init is None else Path(init).name]).encode())
    if init is not None:  # the weights it starts from, not the file's name (every run's is split1-flow.pt)
        h.update(Path(init).read_bytes())
    for name in sorted(data):
        for clip in data[name]:
            h.update(f"{name}\0{clip.key}\0{clip.label}\0{clip.rgb.shape}\n".encode())
            # every frame's pixels and flow as stored (size, flow source): a dataset re-rendered
            # in place differs anywhere, not only in a clip's first frame
            h.update(np.ascontiguousarray(clip.rgb).data)
            h.update(np.ascontiguousarray(clip.flow).data)
    return h.hexdigest()


def _save(path: Path, state: dict[str, Any]) -> None:
    """torch.save through a temporary file and a rename (never a half-written checkpoint)."""
    import torch  # optional extra phav[train]: only training needs torch

    buffer = io.BytesIO()
    torch.save(state, buffer)
    with atomic_write(path) as tmp:
        tmp.write_bytes(buffer.getvalue())


def load_checkpoint(path: str | Path) -> dict[str, Any]:
    """A checkpoint's contents; a damaged or foreign file is a PhavUserError."""
    import torch  # optional extra phav[train]: only training needs torch

    try:
        # weights_only: a checkpoint is data (tensors, numbers, strings); it can never run code.
        state = torch.load(Path(path), map_location="cpu", weights_only=True)
    except FileNotFoundError:
        raise PhavUserError("no such checkpoint", source=str(path)) from None
    except Exception as e:  # torch raises many types for damaged files
        raise PhavUserError(f"not a readable checkpoint ({type(e).__name__})", source=str(path)) from None
    if not isinstance(state, dict) or state.get("format") != "phav-tsn-1":
        raise PhavUserError("not a phav TSN checkpoint", source=str(path))
    return state


def train(
    data: Mapping[str, Sequence[Clip]],
    heads: Mapping[str, int],
    config: TrainConfig,
    *,
    checkpoint: str | Path | None = None,
    init: str | Path | None = None,
    max_seconds: float | None = None,
    progress: Callable[[Epoch, int], None] | None = None,
    after_epoch: Callable[[TrainResult], None] | None = None,
    device: str = "cpu",
    teacher: Teacher | None = None,
) -> TrainResult:
    """Train one stream on ``data`` (source → training clips) with a head per source.

    Args:
        heads: classes per source (its head's width).
        checkpoint: written after every epoch; when it exists, training resumes from it.
        init: a checkpoint whose backbone starts this model (TSN-FT); heads start afresh.
        max_seconds: stop at the last epoch boundary that fits in this many seconds of
            training (then the result depends on the machine's speed, and says so).
        progress: called after every epoch with the record and the total epochs.
        after_epoch: called after every epoch with the result so far (to test the model
            as it trains; it is put back in training mode afterwards).
        device: where the model runs (``cpu``, ``cuda``, ``cuda:1``); random draws stay on the CPU.
        teacher: the flow stream an RGB stream with ``distill`` learns from.
    """
    require_torch()
    import torch  # optional extra phav[train]: only training needs torch

    for name in config.sources:
        if name not in heads:
            raise PhavUserError(f"no classes given for source {name!r}", field="--mix")
    if (config.distill > 0) != (teacher is not None):
        raise PhavUserError("distillation needs both a weight and a trained flow stream", field="--distill")
    dev = torch_device(device)
    with torch_threads(config.threads), cutting(dev, config.threads) as cutter:
        gen = torch.Generator().manual_seed(config.seed)
        model = _model(config, heads, init, gen, dev)
        if teacher is not None:
            if teacher.model.backbone.out_features != model.backbone.out_features:
                raise PhavUserError("the flow teacher's features are not as wide as this stream's", field="--widths")
            teacher.model.to(dev)
        opt = torch.optim.SGD(model.parameters(), lr=config.lr, momentum=config.momentum,
                              weight_decay=config.weight_decay)  # fmt: skip
        rng = seeded_rng(config.seed)
        without_teacher = _fingerprint(config, data, heads, init)
        fingerprint = without_teacher
        if teacher is not None:
            fingerprint = hashlib.sha256(f"{fingerprint}\0{teacher.digest()}".encode()).hexdigest()
        ckpt = Path(checkpoint) if checkpoint is not None else None
        resumed = _resumable(ckpt, fingerprint, without_teacher if teacher is not None else None)
        batches = MixedBatches({name: list(range(len(data[name]))) for name in config.sources}, config.mix, rng=rng)
        run = _Run(data, heads, config, fingerprint, model, opt, rng, gen, batches, dev, teacher, cutter,
                   without_teacher)  # fmt: skip
        result = TrainResult(model, config)
        if resumed is not None:
            run.restore(resumed, result)
        model.train()
        for epoch in range(len(result.history), config.epochs):
            last = result.history[-1].seconds if result.history else 0.0
            if max_seconds is not None and result.seconds + last > max_seconds:
                result.stopped_on_time = True
                break
            record = run.epoch(epoch)
            result.history.append(record)
            result.seconds += record.seconds
            if ckpt is not None:
                _save(ckpt, run.checkpoint(result))
            if progress is not None:
                progress(record, config.epochs)
            if after_epoch is not None:
                after_epoch(result)
                model.train()
        model.eval()
        return result


def _model(config: TrainConfig, heads: Mapping[str, int], init: str | Path | None, gen: Any, dev: Any) -> Any:
    """The TSN, initialised from ``gen`` (its backbone from ``init`` for TSN-FT), on ``dev``."""
    from phav_validators.learn.model import TSN, channels_last  # imports torch: optional extra phav[train]

    model = TSN(in_channels(config.stream, config.flow_frames, config.rgb_frames), heads, config.arch, generator=gen)
    if init is not None:
        _init_backbone(model, load_checkpoint(init), init)
    if config.precision == "fp32":  # faster there; bfloat16 kept its measured (default) layout
        channels_last(model)
    model.to(dev)  # before the optimiser, whose state must live beside the parameters
    return model


def _resumable(ckpt: Path | None, fingerprint: str, without_teacher: str | None = None) -> dict[str, Any] | None:
    """The checkpoint to resume, None to start afresh; one made for other settings or data is an
    error. One that differs only in its teacher (``without_teacher``: a flow stream the budget
    stopped, trained on since) starts afresh: distilled from a teacher that has moved on, it
    is not what an uninterrupted run against today's teacher reaches."""
    if ckpt is None or not ckpt.exists():
        return None
    state = load_checkpoint(ckpt)
    if state["fingerprint"] == fingerprint:
        return state
    if without_teacher is not None and state.get("fingerprint_without_teacher") == without_teacher:
        return None
    raise PhavUserError("made with other settings or data; delete it or choose another output", source=str(ckpt))


def _in_turn(f: Callable[[Any], Any], items: Sequence[Any]) -> list[Any]:
    """``Mapper`` without threads: ``f`` of each item, one after another."""
    return [f(item) for item in items]


@dataclass
class _Run:
    """One training run's moving parts: what a step updates and what a checkpoint keeps."""

    data: Mapping[str, Sequence[Clip]]
    heads: Mapping[str, int]
    config: TrainConfig
    fingerprint: str
    model: Any  # phav_validators.learn.model.TSN
    opt: Any  # torch.optim.Optimizer
    rng: np.random.Generator
    gen: Any  # torch.Generator
    batches: MixedBatches
    device: Any  # torch.device
    teacher: Teacher | None = None
    #: Maps a function over a batch's clips (``cutting``): in turn or in a thread pool.
    cutter: Mapper = _in_turn
    #: The fingerprint less the teacher's weights (``_resumable``).
    fingerprint_without_teacher: str | None = None

    @property
    def steps_per_epoch(self) -> int:
        """Steps that show the model about as many clips as the sources hold."""
        n_train = sum(len(self.data[name]) for name in self.config.sources)
        return max(1, math.ceil(n_train / self.config.batch))

    def restore(self, state: Mapping[str, Any], result: TrainResult) -> None:
        """Continue from a checkpoint: weights, optimiser, random states, batches and history."""
        self.model.load_state_dict(state["model"])
        self.opt.load_state_dict(state["optimizer"])
        self.rng.bit_generator.state = state["numpy_rng"]
        self.gen.set_state(state["torch_rng"])
        result.history = [Epoch(**e) for e in state["history"]]
        result.seconds = state["seconds"]
        result.resumed_from = len(result.history)
        self.batches.load_state(state["batches"])

    def checkpoint(self, result: TrainResult) -> dict[str, Any]:
        """Everything ``restore`` needs to reach the weights an uninterrupted run reaches."""
        return {
            "format": "phav-tsn-1", "fingerprint": self.fingerprint,
            "fingerprint_without_teacher": self.fingerprint_without_teacher, "config": self.config.to_json(),
            "heads": dict(self.heads), "model": self.model.state_dict(), "optimizer": self.opt.state_dict(),
            "numpy_rng": self.rng.bit_generator.state, "torch_rng": self.gen.get_state(),
            "batches": self.batches.state(), "history": [asdict(e) for e in result.history],
            "seconds": result.seconds,
        }  # fmt: skip

    def epoch(self, epoch: int) -> Epoch:
        """One epoch's steps; its record holds the mean loss per source and the training accuracy.
        The next batch is not cut while the model computes: torch's threads already fill the
        cores, so a second thread only competes with them (docs/experiments/learnability.md,
        "The defaults and why")."""
        names = self.config.sources
        start = time.perf_counter()
        sums = {name: [0.0, 0] for name in names}
        correct = seen = 0
        for step in range(self.steps_per_epoch):
            batch, pairs = self._cut()
            scores, labels, sources, parts = self._step(epoch, step, batch, pairs)
            for name, part in parts.items():
                k = int((sources == names.index(name)).sum())
                sums[name][0] += part.item() * k
                sums[name][1] += k
            for z, name in enumerate(names):
                mine = sources == z
                correct += int((scores[name][mine].argmax(1) == labels[mine]).sum())
            seen += len(batch)
        return Epoch(epoch + 1, {n: s / max(k, 1) for n, (s, k) in sums.items()}, correct / max(seen, 1),
                     time.perf_counter() - start)  # fmt: skip

    def _cut(self) -> tuple[list[tuple[str, int]], list[tuple[np.ndarray, dict[str, np.ndarray]]]]:
        """The next mini-batch and its clips' snippets and targets (random crops and flips):
        every place drawn first, in order, then the clips cut (in threads off the CPU)."""
        batch = self.batches.next()
        teacher = self.teacher.config if self.teacher is not None else None
        clips = [self.data[s][i] for s, i in batch]
        places = [draw_cut(clip, self.config, rng=self.rng) for clip in clips]
        return batch, self.cutter(lambda pair: cut_clip(pair[0], self.config, pair[1], teacher=teacher),
                                  list(zip(clips, places, strict=True)))  # fmt: skip

    def _step(
        self,
        epoch: int,
        step: int,
        batch: Sequence[tuple[str, int]],
        pairs: Sequence[tuple[np.ndarray, Mapping[str, np.ndarray]]],
    ) -> tuple[Any, Any, Any, dict[str, Any]]:
        """One mini-batch at the cosine-decayed learning rate: the scores per head, the
        labels, each clip's source index and the loss per source."""
        import torch  # optional extra phav[train]: only training needs torch

        from phav_validators.learn.model import multitask_loss  # imports torch: optional extra phav[train]

        config, names, dev = self.config, self.config.sources, self.device
        total_steps = self.steps_per_epoch * config.epochs
        lr = config.lr * 0.5 * (1.0 + math.cos(math.pi * (epoch * self.steps_per_epoch + step) / total_steps))
        for group in self.opt.param_groups:
            group["lr"] = lr
        x = torch.from_numpy(np.stack([p[0] for p in pairs])).to(dev)
        labels = torch.tensor([self.data[s][i].label for s, i in batch], device=dev)
        sources = torch.tensor([names.index(s) for s, _ in batch], device=dev)
        with autocast(config, dev):
            scores, more = self.model(x, generator=self.gen, extras=True)
        scores = {name: v.float() for name, v in scores.items()}  # the losses in float32
        more = {name: v.float() for name, v in more.items()}
        loss, parts = multitask_loss(scores, labels, sources, names)
        if self.teacher is not None:
            loss = loss + config.distill * self.teacher.loss(more["features"], [p[1] for p in pairs])
        if not torch.isfinite(loss):
            raise PhavUserError(f"training diverged at epoch {epoch + 1}, step {step + 1} "
                                f"(loss {loss.item()}); lower the learning rate", field="--lr")  # fmt: skip
        self.opt.zero_grad(set_to_none=True)
        loss.backward()
        torch.nn.utils.clip_grad_norm_(self.model.parameters(), CLIP_GRAD[self.config.stream])
        self.opt.step()
        return scores, labels, sources, parts


def _init_backbone(model: Any, state: Mapping[str, Any], source: str | Path) -> None:
    """Copy a checkpoint's backbone into ``model`` (TSN-FT); the shapes must agree."""
    backbone = {k.removeprefix("backbone."): v for k, v in state["model"].items() if k.startswith("backbone.")}
    try:
        model.backbone.load_state_dict(backbone)
    except RuntimeError:
        raise PhavUserError("its backbone has another stream or architecture than this run",
                            source=str(source)) from None  # fmt: skip


def predict(
    model: Any, clips: Sequence[Clip], config: TrainConfig, head: str, *, batch: int = 32, device: str = "cpu"
) -> np.ndarray:
    """Class probabilities (N, classes) of ``head``: ``test_segments`` centre snippets per clip."""
    import torch  # optional extra phav[train]: only training needs torch

    dev = torch_device(device)
    model.to(dev)
    model.eval()
    out = []

    def centre(clip: Clip) -> np.ndarray:
        return snippets(clip, config, rng=None, segments=config.test_segments)

    with torch_threads(config.threads), cutting(dev, config.threads) as cutter, torch.no_grad(), autocast(config, dev):
        for i in range(0, len(clips), batch):
            x = torch.from_numpy(np.stack(cutter(centre, clips[i : i + batch]))).to(dev)
            out.append(torch.softmax(model(x)[head].float(), dim=1).cpu().numpy())
    n = model.heads[head].out_features
    return np.concatenate(out) if out else np.zeros((0, n), np.float32)


def fuse(scores: Mapping[str, np.ndarray]) -> np.ndarray:
    """Late fusion: the streams' class probabilities averaged with TSN's weights (RGB 1, flow 1.5)."""
    total = sum(FUSION_WEIGHTS[s] for s in scores)
    return sum(FUSION_WEIGHTS[s] * p for s, p in scores.items()) / total


def torch_device(name: str) -> Any:
    """The torch device ``cpu``, ``cuda`` or ``cuda:N``; another name, or a GPU this machine
    lacks, is a PhavUserError."""
    require_torch()
    import torch  # optional extra phav[train]: only training needs torch

    if not _DEVICE.fullmatch(name):
        raise PhavUserError(f"choose cpu, cuda or cuda:N, got {name!r}", field="--device")
    dev = torch.device(name)
    if dev.type == "cuda" and not torch.cuda.is_available():
        raise PhavUserError("CUDA is not available on this machine (torch sees no GPU)", field="--device")
    if dev.index is not None and dev.index >= torch.cuda.device_count():
        raise PhavUserError(f"no GPU {name!r} on this machine; torch counts {torch.cuda.device_count()}, "
                            "numbered from cuda:0", field="--device")  # fmt: skip
    if dev.type == "cuda":  # its fastest convolutions' backward passes sum in any order
        torch.backends.cudnn.deterministic = True
        torch.backends.cudnn.benchmark = False
    return dev


@contextlib.contextmanager
def cutting(device: Any, threads: int) -> Iterator[Mapper]:
    """How a batch's clips are cut into snippets: one after another when the model runs on
    the CPU (torch's threads fill the cores, so cutting threads would only compete with
    them), by ``threads`` threads when it runs on a GPU and the cores are free. OpenCV and
    numpy's copies release the GIL; the order of the results is the batch's either way."""
    if device.type == "cpu" or threads < 2:
        yield _in_turn
        return
    with ThreadPoolExecutor(threads, thread_name_prefix="phav-cut") as pool:
        yield lambda f, items: [*pool.map(f, items)]


@contextlib.contextmanager
def torch_threads(n: int) -> Iterator[None]:
    """Torch computes with ``n`` threads inside, and with as many as before after."""
    import torch  # optional extra phav[train]: only training needs torch

    before = torch.get_num_threads()
    torch.set_num_threads(n)
    try:
        yield
    finally:
        torch.set_num_threads(before)


def autocast(config: TrainConfig, device: Any) -> Any:
    """The forward pass's arithmetic context: bfloat16 autocast under ``precision: bf16``."""
    import torch  # optional extra phav[train]: only training needs torch

    return torch.autocast(torch.device(device).type, dtype=torch.bfloat16, enabled=config.precision == "bf16")


def default_stem_pool(device: str = "cpu") -> bool:
    """Whether the stem is max-pooled by default on ``device``: ``RECOMMENDED``'s choice on a
    CPU, where time binds and the pooled network trains its schedules sooner, as accurate;
    not on a GPU, where time does not bind and the unpooled network scored better
    (docs/experiments/learnability.md, "The defaults and why" and "On a GPU")."""
    return RECOMMENDED.stem_pool and torch_device(device).type == "cpu"


def default_precision(device: str = "cpu") -> str:
    """``bf16`` where ``device`` computes bfloat16 faster than float32, else ``fp32``: a GPU
    from Ampere on; a CPU with AMX; an AMD CPU with AVX-512 BF16. AVX-512 BF16 alone on
    Intel is not enough: without AMX a step was slower in bfloat16 than in float32
    (docs/experiments/learnability.md, "On a CPU without AMX" and "On an AMD EPYC"). Results are
    reproducible per precision, as per thread count, and every run's settings name it."""
    require_torch()
    import torch  # optional extra phav[train]: only training needs torch

    dev = torch_device(device)
    if dev.type == "cuda":
        return "bf16" if torch.cuda.is_bf16_supported() else "fp32"
    vendor, flags = _cpu_info()
    fast = "amx_bf16" in flags or (vendor == "AuthenticAMD" and "avx512_bf16" in flags)
    return "bf16" if fast else "fp32"


def _cpu_info() -> tuple[str, set[str]]:
    """The CPU's vendor and feature flags (empty where there is no /proc/cpuinfo)."""
    fields = cpu_fields()
    return fields.get("vendor_id", ""), set(fields.get("flags", "").split())


def default_threads() -> int:
    """Torch threads when none are asked for: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)
