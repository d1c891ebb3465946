"""Milliseconds per training step of the TSN model alone (no snippet cutting) under each
arithmetic and layout: float32, channels-last, bfloat16 autocast, two smaller networks,
then, in this machine's default arithmetic (bfloat16 where it is faster, else float32 channels-last),
the backbones of the width/depth experiments and the stored sizes
(docs/experiments/learnability.md, "Backbone" and "Stored size and crop").

    .venv/bin/python docs/measure/train_speed.py --threads 2
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Iterable

import torch

from phav_validators.learn.config import Architecture
from phav_validators.learn.data import DEFAULT_SIZE
from phav_validators.learn.model import TSN
from phav_validators.learn.model import channels_last as channels_last_weights
from phav_validators.learn.train import TrainConfig, crop_box, default_precision


def step_ms(
    arch: Architecture,
    *,
    bf16: bool,
    channels_last: bool,
    channels: int,
    steps: int,
    warm: int,
    size: tuple[int, int] = DEFAULT_SIZE,
) -> float:
    """Mean milliseconds of one forward, backward and SGD step on a batch of 32 clips × 3
    snippets of ``channels`` × the 7/8 crop of ``size`` (56 × 74 for 85×64), after ``warm`` steps."""
    gen = torch.Generator().manual_seed(0)
    model = TSN(channels, {"virtual": 35}, arch, generator=gen)
    opt = torch.optim.SGD(model.parameters(), lr=0.01, momentum=0.9)
    height, width = crop_box((size[1], size[0]), TrainConfig.crop)
    x = torch.randn(32 * 3, channels, height, width, generator=gen)
    y = torch.randint(0, 35, (32,), generator=gen)
    if channels_last:
        channels_last_weights(model)  # as training does: the 2D convolutions' weights only
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
    timed = {"channels": args.channels, "steps": args.steps, "warm": 3}
    arithmetics = [
        ("float32", Architecture(), False, False),
        ("float32, channels-last", Architecture(), False, True),
        ("bfloat16 autocast", Architecture(), True, False),
        ("bfloat16 autocast, channels-last", Architecture(), True, True),
        ("float32, max-pool after the stem", Architecture(stem_pool=True), False, False),
        ("float32, widths 24-48-96-192", Architecture(widths=(24, 48, 96, 192)), False, False),
    ]
    print_table(
        "network, arithmetic / layout",
        "against float32",
        ((name, step_ms(arch, bf16=bf16, channels_last=last, **timed)) for name, arch, bf16, last in arithmetics),
    )
    here = default_precision() == "bf16"
    experiments = [
        ("the default network (32-64-128-192)", Architecture(), DEFAULT_SIZE),
        ("widths 48-96-192-256", Architecture(widths=(48, 96, 192, 256)), DEFAULT_SIZE),
        ("widths 32-64-128-192-256 (a block more)", Architecture(widths=(32, 64, 128, 192, 256)), DEFAULT_SIZE),
        ("stored at 128×96", Architecture(), (128, 96)),
        ("stored at 170×128", Architecture(), (170, 128)),
    ]
    print()
    print_table(
        f"network, in this machine's default arithmetic ({'bfloat16' if here else 'float32, channels-last'})",
        "against the default network",
        (
            (name, step_ms(arch, bf16=here, channels_last=not here, size=size, **timed))
            for name, arch, size in experiments
        ),
    )


def print_table(first: str, ratio: str, rows: Iterable[tuple[str, float]]) -> None:
    """A markdown table of milliseconds per step, each row also as a ratio to the first;
    rows are printed as they are timed."""
    print(f"| {first} | ms per step | {ratio} |")
    print("| --- | ---: | ---: |")
    base = None
    for name, ms in rows:
        base = base or ms
        print(f"| {name} | {ms:.0f} | {ms / base:.2f} |", flush=True)


if __name__ == "__main__":
    main()
