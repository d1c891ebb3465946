"""TSN and Cool-TSN in plain torch (paper Section "Cool Temporal Segment Networks").

A TSN stream is one CNN ``F(T_k; W)`` applied to each of K snippets of a video, whose
per-snippet class scores are averaged (the segmental consensus ``G``). Cool-TSN keeps the
backbone shared and gives each source (real, virtual) its own consensus, fully-connected
prediction and softmax loss, weighted by the source's share of the mini-batch. The
backbone is a small CNN sized for CPU training; its widths are configurable.

Randomness (weight init, dropout) comes from an explicit ``torch.Generator``: nothing
here reads torch's global random state.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence

import torch
from torch import Tensor, nn
from torch.nn import functional as F

from phav_validators.learn.config import Architecture


def _conv(c_in: int, c_out: int, kernel: int, stride: int) -> list[nn.Module]:
    return [nn.Conv2d(c_in, c_out, kernel, stride, kernel // 2, bias=False), nn.BatchNorm2d(c_out), nn.ReLU()]


class Backbone(nn.Module):
    """Snippets (N, C, H, W) → features (N, widths[-1])."""

    def __init__(self, channels: int, arch: Architecture):
        super().__init__()
        w = arch.widths
        layers = _conv(channels, w[0], 5, 2)
        if arch.stem_pool:
            layers.append(nn.MaxPool2d(3, 2, 1))
        for c_in, c_out in itertools.pairwise(w):
            layers += _conv(c_in, c_out, 3, 2) + _conv(c_out, c_out, 3, 1)
        self.features = nn.Sequential(*layers)
        self.out_features = w[-1]

    def forward(self, x: Tensor) -> Tensor:
        """Global average pooling of the last feature map."""
        return self.feature_map(x).mean(dim=(2, 3))

    def feature_map(self, x: Tensor) -> Tensor:
        """The last feature map (N, widths[-1], h, w), in channels-last layout when the
        weights are (``channels_last``)."""
        if self.features[0].weight.is_contiguous(memory_format=torch.channels_last):
            x = x.contiguous(memory_format=torch.channels_last)
        return self.features(x)


class TSN(nn.Module):
    """One stream: shared backbone, then per source a classifier and average consensus.

    ``heads`` maps a source name to its number of classes (one entry: plain TSN)."""

    def __init__(self, channels: int, heads: Mapping[str, int], arch: Architecture, *, generator: torch.Generator):
        super().__init__()
        if not heads:
            raise ValueError("TSN needs at least one head")
        self.backbone = Backbone(channels, arch)
        self.dropout = arch.dropout
        self.heads = nn.ModuleDict({name: nn.Linear(self.backbone.out_features, n) for name, n in heads.items()})
        init_weights(self, generator=generator)

    def forward(
        self, snippets: Tensor, *, generator: torch.Generator | None = None, extras: bool = False
    ) -> dict[str, Tensor] | tuple[dict[str, Tensor], dict[str, Tensor]]:
        """(B, K, C, H, W) → per head the consensus scores ``G`` (B, classes); with
        ``extras`` also ``features``, each snippet's pooled features before dropout (B·K, C).

        In training mode dropout needs ``generator``; in eval mode it is the identity."""
        b, k = snippets.shape[:2]
        pooled = self.backbone(snippets.flatten(0, 1))
        features = pooled
        if self.training and self.dropout > 0:
            if generator is None:
                raise ValueError("training-mode forward needs a generator (dropout)")
            features = dropout(features, self.dropout, generator=generator)
        scores = {name: head(features).view(b, k, -1).mean(dim=1) for name, head in self.heads.items()}
        return (scores, {"features": pooled}) if extras else scores


def dropout(x: Tensor, p: float, *, generator: torch.Generator) -> Tensor:
    """Inverted dropout with masks drawn from ``generator`` (``F.dropout`` uses global state)."""
    keep = torch.rand(x.shape, generator=generator, dtype=x.dtype).to(x.device) >= p
    return x * keep / (1.0 - p)


def channels_last(module: nn.Module) -> None:
    """Every 2D convolution's weights in channels-last layout, which the backbone's inputs
    then follow: float32 convolutions run faster so on a CPU (docs/experiments/learnability.md,
    "On a CPU without AMX"). Only the arithmetic's order changes, not the function."""
    for m in module.modules():
        if isinstance(m, nn.Conv2d):
            m.weight.data = m.weight.data.contiguous(memory_format=torch.channels_last)


def init_weights(module: nn.Module, *, generator: torch.Generator) -> None:
    """Kaiming-normal convolutions, small normal classifiers, BN at (1, 0): all from ``generator``."""
    for m in module.modules():
        if isinstance(m, nn.Conv2d):
            nn.init.kaiming_normal_(m.weight, mode="fan_out", nonlinearity="relu", generator=generator)
        elif isinstance(m, nn.Linear):
            nn.init.normal_(m.weight, 0.0, 0.01, generator=generator)
            nn.init.zeros_(m.bias)
        elif isinstance(m, nn.BatchNorm2d):
            nn.init.ones_(m.weight)
            nn.init.zeros_(m.bias)


def multitask_loss(
    scores: Mapping[str, Tensor], labels: Tensor, sources: Tensor, names: Sequence[str]
) -> tuple[Tensor, dict[str, Tensor]]:
    """The paper's loss ``Σ_z δ(y ∈ C_z) w_z L_z(y, G)`` over a mixed mini-batch.

    ``sources[i]`` indexes ``names`` (the head that sample i belongs to); ``w_z`` is source
    z's share of the batch and ``L_z`` its softmax loss, averaged over its own samples. A
    source absent from the batch contributes nothing (and no NaN).

    Returns:
        the total loss and each present source's unweighted loss.
    """
    total = scores[names[0]].new_zeros(())
    parts: dict[str, Tensor] = {}
    n = labels.shape[0]
    for z, name in enumerate(names):
        mine = sources == z
        count = int(mine.sum())
        if count == 0:
            continue
        loss = F.cross_entropy(scores[name][mine], labels[mine])
        parts[name] = loss
        total = total + (count / n) * loss
    return total, parts
