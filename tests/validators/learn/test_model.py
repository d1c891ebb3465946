"""TSN / Cool-TSN pieces: the multi-task loss, its numerical stability, the backbone's shapes."""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch
from torch.nn import functional as F

from phav_spec.errors import PhavUserError
from phav_validators.learn.config import Architecture, in_channels
from phav_validators.learn.model import TSN, channels_last, dropout, multitask_loss


def _model(stream: str = "flow", heads=None, seed: int = 0) -> TSN:
    g = torch.Generator().manual_seed(seed)
    return TSN(in_channels(stream, 5), heads or {"virtual": 35}, Architecture((8, 16, 24)), generator=g)


def test_consensus_averages_the_segments_scores():
    model = _model("rgb", {"virtual": 4}).eval()
    x = torch.randn(2, 3, 3, 24, 32, generator=torch.Generator().manual_seed(1))
    per_snippet = model.heads["virtual"](model.backbone(x.flatten(0, 1))).view(2, 3, 4)
    assert torch.allclose(model(x)["virtual"], per_snippet.mean(dim=1), atol=1e-6)


def test_multitask_loss_weights_each_source_by_its_share_of_the_batch():
    g = torch.Generator().manual_seed(0)
    scores = {"virtual": torch.randn(8, 35, generator=g), "real": torch.randn(8, 5, generator=g)}
    sources = torch.tensor([0, 0, 0, 1, 1, 1, 1, 1])
    labels = torch.tensor([3, 30, 7, 0, 4, 2, 2, 1])
    total, parts = multitask_loss(scores, labels, sources, ["virtual", "real"])
    lv = F.cross_entropy(scores["virtual"][:3], labels[:3])
    lr = F.cross_entropy(scores["real"][3:], labels[3:])
    assert torch.allclose(parts["virtual"], lv) and torch.allclose(parts["real"], lr)
    assert torch.allclose(total, 3 / 8 * lv + 5 / 8 * lr)


def test_multitask_loss_is_the_paper_formula_per_sample():
    """L_z(y, G) = −Σ_i y_i (G_i − log Σ_j exp G_j) over the source's own classes only."""
    g = torch.Generator().manual_seed(2)
    scores = {"virtual": torch.randn(1, 6, generator=g), "real": torch.randn(1, 3, generator=g)}
    total, _ = multitask_loss(scores, torch.tensor([2]), torch.tensor([1]), ["virtual", "real"])
    G = scores["real"][0]
    assert math.isclose(float(total), float(-(G[2] - torch.logsumexp(G, 0))), rel_tol=1e-6)


def _loss_and_grads(model: TSN, x, labels, sources, names):
    model.train()
    scores = model(x, generator=torch.Generator().manual_seed(0))
    loss, _ = multitask_loss(scores, labels, sources, names)
    model.zero_grad()
    loss.backward()
    grads = [p.grad for p in model.parameters() if p.grad is not None]
    return loss, grads


@pytest.mark.parametrize("case", ["source_absent", "one_class_only", "all_invalid_flow", "imbalance_100_to_1"])
def test_loss_and_gradients_stay_finite(case):
    model = _model("flow", {"virtual": 35, "real": 5})
    g = torch.Generator().manual_seed(3)
    n = 8
    x = torch.randn(n, 3, 10, 24, 32, generator=g)
    labels = torch.randint(0, 5, (n,), generator=g)
    sources = torch.tensor([0, 1] * (n // 2))
    if case == "source_absent":
        sources = torch.ones(n, dtype=torch.long)  # no virtual clip in the batch
    elif case == "one_class_only":
        labels = torch.zeros(n, dtype=torch.long)
    elif case == "all_invalid_flow":
        x = torch.zeros_like(x)  # invalid flow is stored as 0: the batch is constant
    elif case == "imbalance_100_to_1":
        n = 101
        x = torch.randn(n, 3, 10, 24, 32, generator=g)
        labels = torch.zeros(n, dtype=torch.long)
        labels[-1] = 4
        sources = torch.ones(n, dtype=torch.long)
    loss, grads = _loss_and_grads(model, x, labels, sources, ["virtual", "real"])
    assert torch.isfinite(loss) and loss.item() > 0
    assert grads and all(torch.isfinite(gr).all() for gr in grads)
    if case == "source_absent":
        assert all(p.grad is None or not p.grad.any() for p in model.heads["virtual"].parameters())


def test_dropout_draws_from_the_given_generator_only():
    x = torch.ones(4, 100)
    a = dropout(x, 0.5, generator=torch.Generator().manual_seed(7))
    torch.manual_seed(0)
    b = dropout(x, 0.5, generator=torch.Generator().manual_seed(7))
    assert torch.equal(a, b)
    assert set(np.unique(a.numpy())) == {0.0, 2.0}


def test_same_generator_seed_gives_the_same_weights():
    a, b, c = _model(seed=5), _model(seed=5), _model(seed=6)
    sa, sb, sc = a.state_dict(), b.state_dict(), c.state_dict()
    assert all(torch.equal(sa[k], sb[k]) for k in sa)
    assert not all(torch.equal(sa[k], sc[k]) for k in sa)


def test_training_forward_without_a_generator_is_refused():
    model = _model().train()
    with pytest.raises(ValueError, match="generator"):
        model(torch.zeros(1, 3, 10, 24, 32))


@pytest.mark.parametrize(("widths", "dropout_p", "field"), [((), 0.5, "--widths"), ((8, 0), 0.5, "--widths"),
                                                            ((8,), 1.0, "--dropout")])  # fmt: skip
def test_bad_architecture_is_a_user_error(widths, dropout_p, field):
    with pytest.raises(PhavUserError) as e:
        Architecture(widths, dropout_p)
    assert e.value.field == field


def test_the_backbone_computes_channels_last_and_the_same_function():
    """In channels-last layout (faster in float32 on the CPU) the 2D convolutions' weights
    and the backbone's activations follow it, and the network computes the contiguous
    layout's function, up to the arithmetic's order."""
    g = torch.Generator().manual_seed(0)
    model = TSN(10, {"virtual": 4}, Architecture((8, 16, 16)), generator=g).eval()
    channels_last(model)
    convs = [m for m in model.modules() if isinstance(m, torch.nn.Conv2d)]
    assert convs and all(m.weight.is_contiguous(memory_format=torch.channels_last) for m in convs)
    x = torch.randn(6, 10, 24, 32, generator=g)  # 2 clips × 3 segments
    fast = model.backbone(x)
    assert model.backbone.feature_map(x).is_contiguous(memory_format=torch.channels_last)
    for m in convs:
        m.weight.data = m.weight.data.contiguous()
    ref = x  # the layers by hand, every tensor in the default layout
    for layer in model.backbone.features:
        ref = layer(ref)
        assert ref.is_contiguous()
    assert torch.allclose(fast, ref.mean(dim=(2, 3)), atol=1e-5)
