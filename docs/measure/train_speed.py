"""Milliseconds per training step of the TSN model alone (no snippet cutting) under each
arithmetic and layout: float32, channels-last, bfloat16 autocast, two smaller networks,
and in bfloat16 the backbones of the width/depth and temporal-model experiments
(docs/learnability.md).

    .venv/bin/python docs/measure/train_speed.py --threads 2
"""

from __future__ import annotations

import argparse
import time

import torch

from phav_validators.learn.config import Architecture
from phav_validators.learn.model import TSN


def step_ms(arch: Architecture, *, bf16: bool, channels_last: bool, channels: int, steps: int, warm: int) -> float:
    """Mean milliseconds of one forward, backward and SGD step on a batch of 32 clips × 3
    snippets of ``channels`` × 56 × 74 (a 7/8 crop of 85×64), after ``warm`` steps."""
    gen = torch.Generator().manual_seed(0)
    model = TSN(channels, {"virtual": 35}, arch, generator=gen)
    opt = torch.optim.SGD(model.parameters(), lr=0.01, momentum=0.9)
    x = torch.randn(32 * 3, channels, 56, 74, generator=gen)
    y = torch.randint(0, 35, (32,), generator=gen)
    if channels_last:
        model = model.to(memory_format=torch.channels_last)
        x = x.contiguous(memory_format=torch.channels_last)
    times = []
    for _ in range(warm + steps):
        start = time.perf_counter()
        with torch.autocast("cpu", dtype=torch.bfloat16, enabled=bf16):
            scores = model(x.unflatten(0, (32, 3)), generator=gen)["virtual"]
        loss = torch.nn.functional.cross_entropy(scores.float(), y)
        opt.zero_grad()
        loss.backward()
        opt.step()
        times.append(time.perf_counter() - start)
    return 1000 * sum(times[warm:]) / steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--channels", type=int, default=10, help="10: the flow stream; 15: 5 RGB frames")
    parser.add_argument("--steps", type=int, default=7)
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    rows = [
        ("float32", Architecture(), False, False),
        ("float32, channels-last", Architecture(), False, True),
        ("bfloat16 autocast", Architecture(), True, False),
        ("bfloat16 autocast, channels-last", Architecture(), True, True),
        ("float32, max-pool after the stem", Architecture(stem_pool=True), False, False),
        ("float32, widths 24-48-96-192", Architecture(widths=(24, 48, 96, 192)), False, False),
        ("bfloat16, widths 48-96-192-256", Architecture(widths=(48, 96, 192, 256)), True, False),
        (
            "bfloat16, widths 32-64-128-192-256 (a block more)",
            Architecture(widths=(32, 64, 128, 192, 256)),
            True,
            False,
        ),
        ("bfloat16, temporal shift (K = 3)", Architecture(temporal_shift=True), True, False),
        ("bfloat16, (2+1)D temporal convolution (K = 3)", Architecture(temporal_conv=True), True, False),
    ]
    base = None
    print("| network, arithmetic / layout | ms per step | against float32 |")
    print("| --- | ---: | ---: |")
    for name, arch, bf16, last in rows:
        ms = step_ms(arch, bf16=bf16, channels_last=last, channels=args.channels, steps=args.steps, warm=3)
        base = base or ms
        print(f"| {name} | {ms:.0f} | {ms / base:.2f} |", flush=True)


if __name__ == "__main__":
    main()
