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


def temporal_shift(x: Tensor, segments: int, fold_div: int = 8) -> Tensor:
    """(B·K, C, H, W) with K = ``segments`` consecutive per clip: the first C/``fold_div``
    channels moved one segment later, the next C/``fold_div`` one earlier, zeros at the ends."""
    n, c = x.shape[:2]
    x = x.view(n // segments, segments, c, *x.shape[2:])
    fold = c // fold_div
    out = torch.zeros_like(x)
    out[:, 1:, :fold] = x[:, :-1, :fold]
    out[:, :-1, fold : 2 * fold] = x[:, 1:, fold : 2 * fold]
    out[:, :, 2 * fold :] = x[:, :, 2 * fold :]
    return out.view(n, c, *x.shape[3:])


class ShiftBlock(nn.Module):
    """``x + conv(shift(x))``: a residual 3×3 convolution over temporally shifted channels."""

    def __init__(self, channels: int):
        super().__init__()
        self.conv = nn.Sequential(*_conv(channels, channels, 3, 1))

    def forward(self, x: Tensor, segments: int) -> Tensor:
        return x + self.conv(temporal_shift(x, segments))


class TemporalConvBlock(nn.Module):
    """``x + relu(bn(conv_t(x)))``: a residual convolution of kernel 3 across the K segments
    of each clip, position by position (the temporal half of a (2+1)D block)."""

    def __init__(self, channels: int):
        super().__init__()
        self.conv = nn.Conv3d(channels, channels, (3, 1, 1), padding=(1, 0, 0), bias=False)
        self.bn = nn.BatchNorm3d(channels)

    def forward(self, x: Tensor, segments: int) -> Tensor:
        n, c, h, w = x.shape
        t = x.view(n // segments, segments, c, h, w).transpose(1, 2)  # (clips, C, K, h, w)
        t = F.relu(self.bn(self.conv(t)))
        return x + t.transpose(1, 2).reshape(n, c, h, w)


#: Blocks that mix a clip's segments: their forward takes the number of segments.
_TEMPORAL = (ShiftBlock, TemporalConvBlock)


class Backbone(nn.Module):
    """Snippets (N, C, H, W) → features (N, widths[-1]); with a temporal model, N is
    clips × ``segments`` in clip order."""

    def __init__(self, channels: int, arch: Architecture):
        super().__init__()
        w = arch.widths
        self.shift = arch.temporal_shift
        self.pool = arch.pool
        layers = _conv(channels, w[0], 5, 2)
        if arch.stem_pool:
            layers.append(nn.MaxPool2d(3, 2, 1))
        #: Where an auxiliary dense head reads: the end of the second stage (or the stem).
        self.tap_index, self.tap_features = len(layers) - 1, w[0]
        for stage, (c_in, c_out) in enumerate(itertools.pairwise(w)):
            layers += _conv(c_in, c_out, 3, 2)
            layers += [ShiftBlock(c_out)] if self.shift else _conv(c_out, c_out, 3, 1)
            if arch.temporal_conv:
                layers.append(TemporalConvBlock(c_out))
            if stage == 0:
                self.tap_index, self.tap_features = len(layers) - 1, c_out
        self.features = nn.Sequential(*layers)
        self.out_features = w[-1]

    def forward(self, x: Tensor, segments: int = 1) -> Tensor:
        return self.pooled(self.feature_maps(x, segments)[0])

    def pooled(self, x: Tensor) -> Tensor:
        """(N, C, h, w) → (N, C) by the architecture's global pooling."""
        return x.mean(dim=(2, 3)) if self.pool == "avg" else x.amax(dim=(2, 3))

    def feature_maps(self, x: Tensor, segments: int = 1) -> tuple[Tensor, Tensor]:
        """The last feature map and the one after the second stage (stride 4, or 8 with
        ``stem_pool``), where an auxiliary dense head reads."""
        if self.features[0].weight.is_contiguous(memory_format=torch.channels_last):  # ``channels_last``
            x = x.contiguous(memory_format=torch.channels_last)
        tap = x
        for i, layer in enumerate(self.features):
            x = layer(x, segments) if isinstance(layer, _TEMPORAL) else layer(x)
            if i == self.tap_index:
                tap = x
        return x, tap


class TSN(nn.Module):
    """One stream: shared backbone, then per source a classifier and average consensus.

    ``heads`` maps a source name to its number of classes (one entry: plain TSN)."""

    def __init__(
        self,
        channels: int,
        heads: Mapping[str, int],
        arch: Architecture,
        *,
        generator: torch.Generator,
        aux_channels: int = 0,
    ):
        super().__init__()
        if not heads:
            raise ValueError("TSN needs at least one head")
        self.backbone = Backbone(channels, arch)
        self.dropout = arch.dropout
        self.heads = nn.ModuleDict({name: nn.Linear(self.backbone.out_features, n) for name, n in heads.items()})
        #: A dense auxiliary head (training only): e.g. the flow between an RGB snippet's frames.
        self.aux = nn.Conv2d(self.backbone.tap_features, aux_channels, 3, 1, 1, bias=False) if aux_channels else None
        init_weights(self, generator=generator)

    def forward(
        self, snippets: Tensor, *, generator: torch.Generator | None = None, extras: bool = False
    ) -> dict[str, Tensor] | tuple[dict[str, Tensor], dict[str, Tensor]]:
        """(B, K, C, H, W) → per head the consensus scores ``G`` (B, classes); with
        ``extras`` also ``features``, each snippet's pooled features before dropout
        (B·K, C), and ``aux``, the auxiliary head's map (B·K, channels, h, w) if it has one.

        In training mode dropout needs ``generator``; in eval mode it is the identity."""
        b, k = snippets.shape[:2]
        last, tap = self.backbone.feature_maps(snippets.flatten(0, 1), k)
        pooled = self.backbone.pooled(last)
        features = pooled
        if self.training and self.dropout > 0:
            if generator is None:
                raise ValueError("training-mode forward needs a generator (dropout)")
            features = dropout(features, self.dropout, generator=generator)
        scores = {name: head(features).view(b, k, -1).mean(dim=1) for name, head in self.heads.items()}
        if not extras:
            return scores
        more = {"features": pooled}
        if self.aux is not None:
            more["aux"] = self.aux(tap)
        return scores, more


def dropout(x: Tensor, p: float, *, generator: torch.Generator) -> Tensor:
    """Inverted dropout with masks drawn from ``generator`` (``F.dropout`` uses global state)."""
    keep = torch.rand(x.shape, generator=generator, dtype=x.dtype).to(x.device) >= p
    return x * keep / (1.0 - p)


def channels_last(module: nn.Module) -> None:
    """Every 2D convolution's weights in channels-last layout, which the backbone's inputs
    then follow: in float32 a flow epoch on 2 cores took 0.88× its time in the default
    layout (docs/learnability.md). Only the arithmetic's order changes, not the function."""
    for m in module.modules():
        if isinstance(m, nn.Conv2d):
            m.weight.data = m.weight.data.contiguous(memory_format=torch.channels_last)


def init_weights(module: nn.Module, *, generator: torch.Generator) -> None:
    """Kaiming-normal convolutions, small normal classifiers, BN at (1, 0): all from ``generator``."""
    for m in module.modules():
        if isinstance(m, (nn.Conv2d, nn.Conv3d)):
            nn.init.kaiming_normal_(m.weight, mode="fan_out", nonlinearity="relu", generator=generator)
        elif isinstance(m, nn.Linear):
            nn.init.normal_(m.weight, 0.0, 0.01, generator=generator)
            nn.init.zeros_(m.bias)
        elif isinstance(m, (nn.BatchNorm2d, nn.BatchNorm3d)):
            nn.init.ones_(m.weight)
            nn.init.zeros_(m.bias)


def multitask_loss(
    scores: Mapping[str, Tensor], labels: Tensor, sources: Tensor, names: Sequence[str], *, smoothing: float = 0.0
) -> tuple[Tensor, dict[str, Tensor]]:
    """The paper's loss ``Σ_z δ(y ∈ C_z) w_z L_z(y, G)`` over a mixed mini-batch.

    ``sources[i]`` indexes ``names`` (the head that sample i belongs to); ``w_z`` is source
    z's share of the batch and ``L_z`` its softmax loss, averaged over its own samples. A
    source absent from the batch contributes nothing (and no NaN). With ``smoothing`` each
    target keeps 1 − smoothing of its probability and spreads the rest evenly over its
    source's classes (label smoothing, Szegedy et al. 2016).

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
        loss = F.cross_entropy(scores[name][mine], labels[mine], label_smoothing=smoothing)
        parts[name] = loss
        total = total + (count / n) * loss
    return total, parts
