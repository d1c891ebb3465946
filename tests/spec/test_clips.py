"""Clips read straight from a dataset's shards (phav_spec.clips) and streamed to a PyTorch
DataLoader (phav_spec.torchdata): exact modalities, TSN frames, every clip once per epoch in
a seeded order, and a resumed iterator that continues where it stopped."""

from __future__ import annotations

import numpy as np
import pytest

from phav_spec.clips import ClipReader, tsn_frames
from phav_spec.encoding import decode_depth, decode_flow
from phav_spec.errors import PhavUserError
from phav_spec.recipe_table import read_recipe_table
from phav_spec.vocab import ACTIONS
from tests.helpers import written_frames

IMAGES = (("rgb", "rgb.png"), ("raw_rgb", "raw.png"), ("semantic", "seg.png"), ("instance", "inst.png"))


def test_a_clip_is_the_writers_frames_exactly(small_dataset):
    reader = ClipReader(small_dataset)
    written = written_frames(small_dataset)
    table = read_recipe_table(small_dataset / "recipes.parquet")
    actions = dict(zip(table.column("video_id"), table.column("action"), strict=True))
    assert reader.video_ids == sorted(actions)
    for vid in reader.video_ids:
        clip = reader.read(vid, modalities=("rgb", "raw_rgb", "semantic", "instance", "depth", "flow", "people"))
        assert clip["label"] == ACTIONS.names.index(actions[vid]) and clip["frames"] == list(range(6))
        for i, f in enumerate(clip["frames"]):
            w = written[f"{vid}/{f:05d}"]
            for name, key in (
                ("rgb", "rgb.png"),
                ("raw_rgb", "raw.png"),
                ("semantic", "seg.png"),
                ("instance", "inst.png"),
            ):
                assert np.array_equal(clip[name][i], w[key]), name
            assert np.array_equal(clip["depth"][i], decode_depth(w["depth.png"]))
            flow, valid = decode_flow(w["flow.png"])
            assert np.array_equal(clip["flow"][i], np.nan_to_num(flow, nan=0.0))
            assert np.array_equal(clip["flow_valid"][i], valid)
            assert clip["people"][i] == w["json"]["people"]


def test_chosen_frames_at_a_smaller_size(small_dataset):
    reader = ClipReader(small_dataset)
    vid = reader.video_ids[0]
    full = reader.read(vid, [1, 4], ("rgb", "flow", "semantic"))
    small = reader.read(vid, [1, 4], ("rgb", "flow", "semantic"), size=(170, 128))
    assert (
        small["frames"] == [1, 4] and small["rgb"].shape == (2, 128, 170, 3) and small["flow"].shape == (2, 128, 170, 2)
    )
    # Vectors are in pixels of the returned size: half the frame, half the motion.
    assert np.allclose(small["flow"].mean(axis=(1, 2)), full["flow"].mean(axis=(1, 2)) / 2, atol=0.05)
    assert set(map(tuple, small["semantic"].reshape(-1, 3))) <= set(map(tuple, full["semantic"].reshape(-1, 3)))


def test_tsn_frames_take_one_frame_per_segment():
    assert tsn_frames(6, 3) == [1, 3, 5] and tsn_frames(2, 3) == [0, 1, 1]
    for seed in range(20):
        picks = tsn_frames(90, 3, np.random.default_rng(seed))
        assert [p // 30 for p in picks] == [0, 1, 2]
    assert tsn_frames(90, 3, np.random.default_rng(7)) == tsn_frames(90, 3, np.random.default_rng(7))
    with pytest.raises(ValueError):
        tsn_frames(0, 3)


def test_resized_flow_averages_valid_vectors_only_and_is_zero_where_invalid():
    from phav_spec.clips import _resize_flow

    flow = np.zeros((1, 4, 8, 2), np.float32)
    valid = np.zeros((1, 4, 8), bool)
    flow[0, :, :3] = (2.0, -1.0)  # the left 2x2-block column wholly valid, the next one in part
    valid[0, :, :3] = True
    out, kept = _resize_flow(flow, valid, (4, 2))  # 2x2 blocks, vectors halved with the size
    assert np.allclose(out[0, :, 0], (1.0, -0.5)) and np.allclose(out[0, :, 1][kept[0, :, 1]], (1.0, -0.5))
    assert not out[0][~kept[0]].any()


def test_bad_requests_are_one_line_errors(small_dataset, tmp_path):
    reader = ClipReader(small_dataset)
    vid = reader.video_ids[0]
    n = reader.n_frames[vid]
    for frames in ([n], [-1], []):  # the video's frames are 0 … n − 1: the shard is not to blame
        with pytest.raises(PhavUserError, match=rf"{vid} frames: frames must be a non-empty list within 0–{n - 1}"):
            reader.read(vid, frames)
    for size in ((0, 64), (64,), (64.5, 48)):
        with pytest.raises(PhavUserError, match=r"size: size must be \(width, height\) in whole pixels"):
            reader.read(vid, [0], size=size)
    with pytest.raises(PhavUserError, match="unknown modalities"):
        reader.read(reader.video_ids[0], modalities=("rgb", "thermal"))
    with pytest.raises(PhavUserError, match="no video 'v999999' with a recipe and frames"):
        reader.read("v999999")
    with pytest.raises(PhavUserError, match=r"no manifest\.json"):
        ClipReader(tmp_path)
    pytest.importorskip("torch")
    from phav_spec.torchdata import PhavClips

    with pytest.raises(PhavUserError, match="modalities: unknown modalities"):  # at once, not in a worker
        PhavClips(small_dataset, modalities=("rgb", "optical_flow"))


def test_damaged_frame_metadata_and_tar_headers_name_the_file(small_dataset_copy):
    """A frame's JSON that does not parse, or lacks what is read, names the member; a tar
    header damaged after the first (which ends tarfile's listing without a word) names the
    damage, not frames missing from the shard."""
    import io
    import tarfile

    shard = small_dataset_copy / "phav-000000.tar"
    with tarfile.open(shard) as tar:
        members = [(m, tar.extractfile(m).read()) for m in tar.getmembers()]

    def rewrite(edit) -> None:
        with tarfile.open(shard, "w", format=tarfile.USTAR_FORMAT) as tar:
            for m, data in members:
                data = edit(m.name, data)
                m.size = len(data)
                tar.addfile(m, io.BytesIO(data))

    first = members[0][0].name.split("/")[0]
    rewrite(lambda name, data: b"{not json" if name == f"{first}/00001.json" else data)
    with pytest.raises(PhavUserError, match=rf"{first}/00001\.json: invalid JSON"):
        ClipReader(small_dataset_copy).read(first, modalities=("people",))
    rewrite(lambda name, data: b'{"camera": {}}' if name == f"{first}/00001.json" else data)
    with pytest.raises(PhavUserError, match=rf"{first}/00001\.json: people: missing"):
        ClipReader(small_dataset_copy).read(first, modalities=("people",))
    rewrite(lambda name, data: data)
    raw = bytearray(shard.read_bytes())
    with tarfile.open(shard) as tar:
        third = tar.getmembers()[2].offset  # a header, not the first
    raw[third + 148 : third + 156] = b"0000000\0"  # its checksum broken
    shard.write_bytes(bytes(raw))
    with pytest.raises(PhavUserError, match=rf"a damaged tar header at byte {third}"):
        ClipReader(small_dataset_copy).read(first, [0], modalities=("rgb",))


def test_a_reader_keeps_few_shards_open_and_a_compact_index(small_dataset, monkeypatch):
    """Loader workers read thousands of shards: open files are capped (the least recently
    read closed), and the index holds a few bytes a member, not an object each."""
    import tracemalloc

    from phav_spec import clips

    monkeypatch.setattr(clips, "MAX_OPEN_SHARDS", 1)
    reader = ClipReader(small_dataset)
    by_shard = {}
    for vid in reader.video_ids:
        by_shard.setdefault(reader._shard_of[vid], vid)
    assert len(by_shard) >= 2
    for vid in [*by_shard.values(), *by_shard.values()]:
        reader.read(vid, [0], modalities=("rgb",))
        assert len(reader._files) == 1
    tracemalloc.start()
    before = tracemalloc.get_traced_memory()[0]
    index = clips._index_shard(next(iter(by_shard)))
    grown = tracemalloc.get_traced_memory()[0] - before
    tracemalloc.stop()
    members = sum(int((o >= 0).sum()) for o in index.offsets.values())
    assert members > 0 and grown / members < 100, grown / members


def _epoch(clips, workers: int) -> list[tuple[str, list[int]]]:
    from torch.utils.data import DataLoader

    from phav_spec.torchdata import collate

    loader = DataLoader(clips, batch_size=clips.batch_size, num_workers=workers, collate_fn=collate)
    return [(vid, f.tolist()) for batch in loader for vid, f in zip(batch["video_id"], batch["frames"], strict=True)]


def test_two_workers_yield_each_clip_once_in_the_seeded_order(small_dataset):
    pytest.importorskip("torch")
    from phav_spec.torchdata import PhavClips

    clips = PhavClips(small_dataset, modalities=("rgb", "flow"), segments=3, size=(85, 64), batch_size=1, seed=5)
    first = _epoch(clips, workers=2)
    assert [v for v, _ in first] == clips.order() and sorted(v for v, _ in first) == clips.videos
    assert first == _epoch(clips, workers=0)  # the same clips and frames whatever the workers
    again = PhavClips(small_dataset, modalities=("rgb", "flow"), segments=3, size=(85, 64), batch_size=1, seed=5)
    assert _epoch(again, workers=2) == first  # the same on every run
    orders = set()
    for epoch in range(6):
        clips.set_epoch(epoch)
        orders.add(tuple(clips.order()))
        assert sorted(v for v, _ in _epoch(clips, workers=2)) == clips.videos
    assert len(orders) > 1


def test_a_resumed_iterator_continues_where_it_stopped(small_dataset):
    pytest.importorskip("torch")
    from phav_spec.torchdata import PhavClips

    clips = PhavClips(small_dataset, modalities=("rgb",), segments=2, batch_size=1, seed=1)
    clips.set_epoch(3)
    whole = _epoch(clips, workers=0)
    state = clips.state_dict(consumed=2)
    fresh = PhavClips(small_dataset, modalities=("rgb",), segments=2, batch_size=1, seed=1)
    fresh.load_state_dict(state)
    assert _epoch(fresh, workers=2) == whole[2:]
    # The module's epoch loop, resumed: set_epoch of the resumed epoch keeps its consumed
    # clips, the next epoch starts whole.
    looped = PhavClips(small_dataset, modalities=("rgb",), segments=2, batch_size=1, seed=1)
    looped.load_state_dict(state)
    looped.set_epoch(3)
    assert _epoch(looped, workers=0) == whole[2:]
    looped.set_epoch(4)
    assert len(_epoch(looped, workers=0)) == len(looped.videos)


def test_replicas_split_an_epoch_as_distributed_sampler_does(small_dataset):
    """Replica r of R reads the clips r, r + R, … of the epoch's order, padded with its first
    videos to a multiple of R: every replica as many clips, every clip read, the frames of a
    clip those its place in the whole epoch draws."""
    pytest.importorskip("torch")
    from phav_spec.torchdata import PhavClips

    whole = PhavClips(small_dataset, modalities=("camera",), segments=2, batch_size=1, seed=4)
    whole.set_epoch(2)
    alone = _epoch(whole, workers=0)
    n = len(whole.videos)
    for world in (2, n + 2):  # more replicas than videos too
        reads = []
        for rank in range(world):
            replica = PhavClips(small_dataset, modalities=("camera",), segments=2, batch_size=1, seed=4,
                                rank=rank, world_size=world)  # fmt: skip
            replica.set_epoch(2)
            reads.append(_epoch(replica, workers=2 if rank == 0 else 0))
            assert len(reads[-1]) == len(replica) == -(-n // world)
        padded = [reads[k % world][k // world] for k in range(world * len(reads[0]))]
        assert padded[:n] == alone  # the repeats pad with the first videos, drawn at their own places
        assert [v for v, _ in padded[n:]] == [v for v, _ in alone * world][: len(padded) - n]
    with pytest.raises(PhavUserError, match="rank must be in"):
        PhavClips(small_dataset, rank=2, world_size=2)


def test_an_initialised_process_group_gives_the_replica(small_dataset, monkeypatch):
    """Without rank and world_size, a DDP run's process group says which replica this is."""
    torch = pytest.importorskip("torch")
    from phav_spec.torchdata import PhavClips

    assert (PhavClips(small_dataset).rank, PhavClips(small_dataset).world_size) == (0, 1)
    monkeypatch.setattr(torch.distributed, "is_initialized", lambda: True)
    monkeypatch.setattr(torch.distributed, "get_world_size", lambda: 3)
    monkeypatch.setattr(torch.distributed, "get_rank", lambda: 1)
    clips = PhavClips(small_dataset)
    assert (clips.rank, clips.world_size) == (1, 3) and len(clips) == -(-len(clips.videos) // 3)
    assert PhavClips(small_dataset, rank=0, world_size=1).world_size == 1  # given, it wins


def test_a_process_group_initialised_after_the_clips_are_made_gives_the_replica(small_dataset, monkeypatch):
    """A training script may make its PhavClips before init_process_group: the group is read
    again at set_epoch, so the replica does not read the whole epoch as if it were alone."""
    torch = pytest.importorskip("torch")
    from phav_spec.torchdata import PhavClips

    clips = PhavClips(small_dataset, shuffle=False)
    assert (clips.rank, clips.world_size, clips.order()) == (0, 1, clips.videos)
    monkeypatch.setattr(torch.distributed, "is_initialized", lambda: True)
    monkeypatch.setattr(torch.distributed, "get_world_size", lambda: 2)
    monkeypatch.setattr(torch.distributed, "get_rank", lambda: 1)
    clips.set_epoch(0)
    padded = (clips.videos * 2)[: -(-len(clips.videos) // 2) * 2]  # as DistributedSampler pads
    assert (clips.rank, clips.world_size) == (1, 2) and clips.order() == padded[1::2]
    assert [vid for vid, _ in _epoch(clips, 0)] == padded[1::2]


def test_an_epochs_order_and_its_clips_frames_are_drawn_from_streams_of_their_own():
    """numpy's seeding pads its words with zeros: (seed, epoch) and (seed, epoch, 0) drew one
    stream, so the first clip's frames followed the order's first draw, and epoch 0's order
    the split's seed (seed). Each stream ends with a salt of its own."""
    from phav_spec.seeding import seeded_rng
    from phav_spec.torchdata import _FRAMES_STREAM, _ORDER_STREAM

    assert seeded_rng(0, 3).random() == seeded_rng(0, 3, 0).random()  # the padding
    for seed in range(3):
        for epoch in range(3):
            order, frames = seeded_rng(seed, epoch, _ORDER_STREAM), seeded_rng(seed, epoch, 0, _FRAMES_STREAM)
            firsts = {order.random(), frames.random(), seeded_rng(seed).random()}
            assert len(firsts) == 3


def test_a_clip_dataset_of_a_size_no_frame_can_have_is_refused_at_once(small_dataset):
    pytest.importorskip("torch")
    from phav_spec.torchdata import PhavClips

    with pytest.raises(PhavUserError, match=r"size: size must be"):
        PhavClips(small_dataset, size=(0, 64))


def test_persistent_workers_follow_set_epoch(small_dataset):
    """Persistent workers keep the dataset object they started with: the epoch reaches them
    all the same (each epoch its own order and frames)."""
    pytest.importorskip("torch")
    from torch.utils.data import DataLoader

    from phav_spec.torchdata import PhavClips, collate

    clips = PhavClips(small_dataset, modalities=("camera",), segments=2, batch_size=1, seed=2)
    loader = DataLoader(clips, batch_size=1, num_workers=2, collate_fn=collate, persistent_workers=True)
    for epoch in range(3):
        clips.set_epoch(epoch)
        got = [(vid, f.tolist()) for b in loader for vid, f in zip(b["video_id"], b["frames"], strict=True)]
        assert got == _epoch(clips, workers=0), epoch


def test_a_clips_metadata_rows_are_the_tables(small_dataset):
    """The per-frame metadata a clip carries is people.parquet's and cameras.parquet's rows,
    NaN for NaN."""
    import pyarrow.parquet as pq

    reader = ClipReader(small_dataset)
    table = pq.read_table(small_dataset / "people.parquet").to_pylist()
    rows = {(r["video_id"], r["frame"], r["person_id"]): r for r in table}
    cameras = {(r["video_id"], r["frame"]): r for r in pq.read_table(small_dataset / "cameras.parquet").to_pylist()}
    seen = 0
    for vid in reader.video_ids:
        clip = reader.read(vid, modalities=("people", "camera"))
        for f, camera in zip(clip["frames"], clip["camera"], strict=True):
            assert all(_nan_equal(camera[k], v) or camera[k] == v for k, v in cameras[(vid, f)].items()), (vid, f)
        for f, people in zip(clip["frames"], clip["people"], strict=True):
            for person in people:
                want = rows[(vid, f, person["person_id"])]
                for key, value in want.items():
                    got = person[key]
                    assert got == value or _nan_equal(got, value), (vid, f, key)
                seen += 1
    assert seen == len(table)


def _nan_equal(a, b) -> bool:
    """JSON writes NaN as null: equal where the table's NaN is the JSON's None."""
    if a is None:
        return isinstance(b, float) and b != b
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(x == y or _nan_equal(x, y) for x, y in zip(a, b, strict=True))
    return a == b
