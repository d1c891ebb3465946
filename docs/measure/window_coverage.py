"""Where the crop placed on the motion lands: the share of the people's pixels inside it
(docs/experiments/learnability.md, "Stored size and crop").

The crop placed on the motion (``--focus motion``, measured there and since gone from
``phav train``) was the window of most median-centred flow, found from the flow alone
(``motion_window``). This measures, per clip at its test snippets, how much of the
body-part pixels of PHAV's semantic frames (any person's; the measurement only, never a
network's input) falls inside that window, inside a window of the same size at the frame's
centre, and inside the default centre crop. It reads ``learn_experiments.py``'s clip cache
by memory map (the cache is stored uncompressed), so a 170×128 cache of 11 GB costs no RAM,
and the measured clips' semantic frames from the shards of the datasets the cache names.

    .venv/bin/python docs/measure/window_coverage.py g21+1.clips-170x128-gt.npz --crop 0.5 --every 7
"""

from __future__ import annotations

import argparse
import json
import re
import zipfile
from collections.abc import Iterable
from pathlib import Path

import cv2
import numpy as np

from phav_spec.encoding import modality
from phav_spec.manifest import load_manifest
from phav_spec.vocab import PIXEL_CLASSES, PixelGroup
from phav_spec.webdataset import decode_png
from phav_validators.checks.tarsafe import TarScan, iter_members
from phav_validators.learn.data import Clip
from phav_validators.learn.train import TrainConfig, crop_box, draw_cut, snippet_frames

#: The zip local file header's fixed length and the offsets of its name and extra lengths.
_LOCAL_HEADER, _NAME_LEN, _EXTRA_LEN = 30, 26, 28


def memmap_npz(path: Path) -> dict[str, np.ndarray]:
    """Each array of an uncompressed ``.npz`` (``np.savez``) as a read-only memory map."""
    arrays = {}
    with zipfile.ZipFile(path) as zf, open(path, "rb") as f:
        for info in zf.infolist():
            if info.compress_type != zipfile.ZIP_STORED:
                raise SystemExit(f"{path}: {info.filename} is compressed; only np.savez files can be mapped")
            f.seek(info.header_offset)
            local = f.read(_LOCAL_HEADER)
            skip = int.from_bytes(local[_NAME_LEN:_NAME_LEN + 2], "little") + int.from_bytes(
                local[_EXTRA_LEN:_EXTRA_LEN + 2], "little")  # fmt: skip
            f.seek(info.header_offset + _LOCAL_HEADER + skip)
            version = np.lib.format.read_magic(f)
            read_header = (
                np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
            )
            shape, fortran, dtype = read_header(f)
            if dtype.hasobject or fortran:
                raise SystemExit(f"{path}: {info.filename} cannot be memory-mapped")
            arrays[info.filename.removesuffix(".npy")] = np.memmap(path, dtype=dtype, mode="r", offset=f.tell(),
                                                                   shape=shape)  # fmt: skip
    return arrays


#: A person in the semantic frames: every body part and joint, either side, any person's.
_BODY_COLOURS = np.array(sorted(
    (c.rgb[0] << 16) | (c.rgb[1] << 8) | c.rgb[2]
    for _, c in PIXEL_CLASSES.items()
    if c.group in (PixelGroup.HUMAN_PARTS, PixelGroup.HUMAN_JOINTS)
), np.int64)  # fmt: skip
_SEMANTIC = re.compile(r"^(v\d+)/(\d+)\.seg\.png$")


def body_mask(semantic: np.ndarray) -> np.ndarray:
    """A semantic frame (H, W, 3) uint8 of PIXEL_CLASSES colours → (H, W) bool: where a
    person's body part or joint is."""
    packed = (semantic[..., 0].astype(np.int64) << 16) | (semantic[..., 1].astype(np.int64) << 8) | semantic[..., 2]
    return np.isin(packed, _BODY_COLOURS)


def read_bodies(root: Path, videos: Iterable[str], size: tuple[int, int]) -> dict[str, np.ndarray]:
    """Each of ``videos``' body masks (T, H, W) bool at ``size`` (width, height), nearest
    neighbour, from the semantic frames of the PHAV dataset at ``root`` (its shards
    streamed, only those members read)."""
    if not (root / "manifest.json").exists():
        raise SystemExit(f"{root}: not a PHAV dataset directory (no manifest.json); its semantic frames are needed")
    wanted = set(videos)
    encoding = modality("semantic")
    frames: dict[str, dict[int, np.ndarray]] = {v: {} for v in wanted}
    for shard in load_manifest(root / "manifest.json").shards:
        mine = wanted.intersection(shard.video_ids)
        if not mine:
            continue

        def only(name: str, mine: set[str] = mine) -> bool:
            m = _SEMANTIC.match(name)
            return m is not None and m.group(1) in mine

        path = root / shard.name
        for name, data in iter_members(path, TarScan(), only=only):
            vid, frame = _SEMANTIC.match(name).groups()  # type: ignore[union-attr]
            body = body_mask(decode_png(data, encoding, source=f"{path}: {name}"))
            frames[vid][int(frame)] = cv2.resize(body.view(np.uint8), size, interpolation=cv2.INTER_NEAREST)
    bodies = {}
    for vid, found in frames.items():
        order = sorted(found)
        if not order or order != list(range(len(order))):
            raise SystemExit(f"{root}: video {vid}'s semantic frames are missing from its shard")
        bodies[vid] = np.stack([found[i] for i in order]) > 0
    return bodies


def motion_window(clip: Clip, frames: np.ndarray, box: tuple[int, int]) -> tuple[int, int]:
    """Top-left (y, x) of the ``box`` (height, width) window holding the most motion in
    ``frames`` of the clip: the flow's magnitude after each frame's median vector (the
    camera's) is removed, summed over every window position. It looks at the flow only,
    as a real video's estimated flow would allow; the centre window when nothing moves."""
    h, w = clip.flow.shape[1:3]
    ch, cw = box
    used = np.unique(frames)
    flow = clip.flow[used].astype(np.float32) - clip.flow_median[used][:, None, None, :]
    magnitude = np.sqrt((flow**2).sum(-1)).sum(0)
    # Sum over every window position: a summed-area table, exact and order-independent.
    table = np.pad(magnitude.astype(np.float64).cumsum(0).cumsum(1), ((1, 0), (1, 0)))
    sums = table[ch:, cw:] - table[:-ch, cw:] - table[ch:, :-cw] + table[:-ch, :-cw]
    if not sums.max() > 0:
        return (h - ch) // 2, (w - cw) // 2
    y0, x0 = np.unravel_index(int(np.argmax(sums)), sums.shape)
    return int(y0), int(x0)


def body_shares(
    clip: Clip, body: np.ndarray, crop: float, default_crop: float = TrainConfig.crop
) -> tuple[float, float, float] | None:
    """Shares of the clip's body-part pixels (``body``: (T, H, W) bool, ``read_bodies``),
    over its flow stream's test snippets, inside (the motion window, a centred window of the
    same size, the default centre crop); None when those frames show no person."""
    config = TrainConfig(stream="flow", seed=0, crop=crop)
    # The test snippets' starts and a centred window of the crop's size.
    cut = draw_cut(clip, config, rng=None, segments=config.test_segments)
    frames = snippet_frames(cut.starts, clip.n_frames, config.flow_frames)
    body = body[np.unique(frames)]
    total = int(body.sum())
    if total == 0:
        return None
    h, w = body.shape[1:]
    ch, cw = cut.box
    y, x = motion_window(clip, frames, (ch, cw))
    dh, dw = crop_box((h, w), default_crop)

    def inside(y0: int, x0: int, bh: int, bw: int) -> float:
        return float(body[:, y0 : y0 + bh, x0 : x0 + bw].sum() / total)

    return inside(y, x, ch, cw), inside(*cut.corner, ch, cw), inside((h - dh) // 2, (w - dw) // 2, dh, dw)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cache", type=Path, help="a learn_experiments.py clip cache (….clips-WxH-FLOW.npz)")
    parser.add_argument("--crop", type=float, default=0.5, help="the motion window's side, share of the frame")
    parser.add_argument("--every", type=int, default=7, help="measure every Nth clip of the cache")
    args = parser.parse_args()
    if not args.cache.exists():
        raise SystemExit(f"{args.cache}: no such cache (learn_experiments.py writes it beside the dataset)")
    arrays = memmap_npz(args.cache)
    meta = json.loads(str(np.load(args.cache)["meta"]))
    cuts = np.cumsum([0] + meta["frames"])
    measured = range(0, len(meta["keys"]), args.every)
    # The measured clips' people, read per dataset: a cache's keys are "<dataset folder>/<video>".
    roots = {Path(r).name: Path(r) for r in meta["roots"]}
    videos: dict[str, list[str]] = {}
    for i in measured:
        dataset, _, video = meta["keys"][i].partition("/")
        videos.setdefault(dataset, []).append(video)
    size = (arrays["rgb"].shape[2], arrays["rgb"].shape[1])
    bodies = {f"{dataset}/{video}": body for dataset, names in videos.items()
              for video, body in read_bodies(roots[dataset], names, size).items()}  # fmt: skip
    shares = []
    for i in measured:
        a, b = cuts[i], cuts[i + 1]
        key = meta["keys"][i]
        clip = Clip(key, meta["labels"][i], "virtual", np.asarray(arrays["rgb"][a:b]), np.asarray(arrays["flow"][a:b]))
        if bodies[key].shape != clip.flow.shape[:3]:
            raise SystemExit(f"{args.cache}: {key} has {clip.n_frames} frames, {len(bodies[key])} in its dataset")
        found = body_shares(clip, bodies[key], args.crop)
        if found is not None:
            shares.append(found)
    if not shares:
        raise SystemExit(f"{args.cache}: no measured clip shows a person")
    s = np.array(shares)
    print(f"{len(s)} clips (every {args.every}th with a person), crop {args.crop} of {args.cache.name}")
    print("| window | body pixels inside, median | mean | clips with under half inside | with none inside |")
    print("| --- | ---: | ---: | ---: | ---: |")
    names = [f"on the most motion ({args.crop})", f"centred, same size ({args.crop})",
             f"the default centre crop ({TrainConfig.crop})"]  # fmt: skip
    for name, v in zip(names, s.T, strict=True):
        print(
            f"| {name} | {100 * np.median(v):.0f} % | {100 * v.mean():.0f} % | {100 * (v < 0.5).mean():.0f} % | "
            f"{100 * (v == 0).mean():.0f} % |"
        )


if __name__ == "__main__":
    main()
