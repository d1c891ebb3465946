"""Clips from PHAV shards (streamed) and from UCF-101 / HMDB-51 folders (PyAV), and splits."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from phav_spec.errors import PhavUserError
from phav_spec.recipe_table import read_recipe_table
from phav_spec.vocab import ACTIONS
from phav_validators.learn.data import Clip, decode_video, hmdb51_split, load_phav, load_real, ucf101_split
from phav_validators.learn.splits import dataset_split, make_split
from tests.helpers import invoke_cli
from tests.validators.learn.helpers import (
    HMDB_CLASSES,
    UCF_CLASSES,
    hmdb51_folder,
    motion_clips,
    moving_square,
    ucf101_folder,
    write_video,
)


def test_phav_clips_carry_actions_actors_and_motions_from_the_recipes(phav):
    clips = load_phav(phav, size=(85, 64))
    table = read_recipe_table(phav / "recipes.parquet")
    recipes = {r.video_id: r for r in table.recipes()}
    assert [c.key for c in clips.clips] == sorted(recipes)
    for clip in clips.clips:
        r = recipes[clip.key]
        assert clip.label == ACTIONS.index(r.action) and clips.classes[clip.label] == r.action
        partner = tuple(c.human.model for c in r.supporting_characters)
        blend = (r.variation.blend_motion,) if r.variation.kind == "action_blending" else ()
        assert clip.groups == {"actor": (r.protagonist.human.model, *partner), "motion": (r.motion.base_motion, *blend),
                               "background": tuple(a.human.model for a in r.background_actors)}  # fmt: skip
        assert clip.rgb.shape == (r.n_frames, 64, 85, 3) and clip.flow.shape == (r.n_frames, 64, 85, 2)
        assert np.isfinite(clip.flow.astype(np.float32)).all()


def test_phav_flow_keeps_its_mean_when_stored_smaller(phav):
    """Area resizing averages the ground-truth flow (invalid counted as 0), vectors scaled."""
    import cv2

    from phav_spec.encoding import decode_flow
    from phav_validators.checks.tarsafe import TarScan, iter_members

    clips = load_phav(phav, size=(85, 64))
    shard = sorted(phav.glob("*.tar"))[0]
    name, data = next((n, d) for n, d in iter_members(shard, TarScan()) if n.endswith("00003.flow.png"))
    code = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)[..., ::-1]
    flow = np.nan_to_num(decode_flow(np.ascontiguousarray(code))[0])
    clip = next(c for c in clips.clips if c.key == name.split("/")[0])
    stored = clip.flow[3].astype(np.float64)
    assert stored[..., 0].mean() == pytest.approx(flow[..., 0].mean() * 85 / 340, abs=2e-3)
    assert stored[..., 1].mean() == pytest.approx(flow[..., 1].mean() * 64 / 256, abs=2e-3)


def test_phav_loading_is_the_same_in_worker_processes(phav):
    one = load_phav(phav, workers=1)
    two = load_phav(phav, workers=2)
    for a, b in zip(one.clips, two.clips, strict=True):
        assert a.key == b.key and np.array_equal(a.rgb, b.rgb) and np.array_equal(a.flow, b.flow)


def test_estimated_flow_replaces_the_ground_truth_on_request(phav):
    gt = load_phav(phav, videos=["v000000"])
    fb = load_phav(phav, videos=["v000000"], flow="farneback")
    assert len(fb) == 1 and fb.clips[0].flow.shape == gt.clips[0].flow.shape
    assert not np.array_equal(fb.clips[0].flow, gt.clips[0].flow)
    assert np.array_equal(fb.clips[0].rgb, gt.clips[0].rgb)


def test_a_shard_missing_frames_is_a_user_error(phav, tmp_path):
    import shutil
    import tarfile

    copy = tmp_path / "data"
    shutil.copytree(phav, copy)
    shard = sorted(copy.glob("*.tar"))[0]
    with tarfile.open(shard) as tar:
        members = [(i, tar.extractfile(i).read()) for i in tar.getmembers() if not i.name.endswith("00002.rgb.png")]
    with tarfile.open(shard, "w") as tar:
        for info, data in members:
            import io

            tar.addfile(info, io.BytesIO(data))
    with pytest.raises(PhavUserError, match="frames missing"):
        load_phav(copy)


def test_not_a_dataset_is_a_user_error(tmp_path):
    with pytest.raises(PhavUserError, match="no manifest"):
        load_phav(tmp_path)


def test_ucf101_layout_and_split_files(tmp_path):
    root = ucf101_folder(tmp_path)
    split = ucf101_split(root, 1)
    assert split.classes == list(UCF_CLASSES)
    assert len(split.train) == 12 and len(split.test) == 6
    assert {v.group for v in split.test} == {"g01"} and "g01" not in {v.group for v in split.train}
    clips = load_real(split.test, size=(32, 24))
    assert [c.label for c in clips] == [v.label for v in split.test]
    assert all(c.source == "real" and c.rgb.shape == (10, 24, 32, 3) for c in clips)
    # the square moves right in class 0 and down in class 1: the estimated flow says so
    right = clips[0].flow[:-1, ..., 0].astype(np.float32).mean()
    down = clips[2].flow[:-1, ..., 1].astype(np.float32).mean()
    assert right > 0.02 and down > 0.02, (right, down)


def test_hmdb51_layout_and_split_files(tmp_path):
    root = hmdb51_folder(tmp_path)
    split = hmdb51_split(root, 2)
    assert split.classes == sorted(HMDB_CLASSES)
    assert len(split.test) == 3 and len(split.train) == 6  # the 0-marked clips are unused
    clips = load_real(split.train, size=(32, 24))
    assert sorted({c.label for c in clips}) == [0, 1, 2]


def test_real_dataset_errors_name_the_file(tmp_path):
    with pytest.raises(PhavUserError, match="ucfTrainTestlist"):
        ucf101_split(tmp_path)
    root = ucf101_folder(tmp_path / "ucf", groups=2, clips=1)
    bad = root / UCF_CLASSES[0] / f"v_{UCF_CLASSES[0]}_g01_c01.avi"
    bad.write_bytes(b"not a video")
    with pytest.raises(PhavUserError) as e:
        load_real(ucf101_split(root, 1).test)
    assert str(bad) in str(e.value)
    (tmp_path / "ucf" / "ucfTrainTestlist" / "classInd.txt").write_text("one Apply\n")
    with pytest.raises(PhavUserError, match="classInd"):
        ucf101_split(root, 1)


def test_decode_video_round_trips_frame_count(tmp_path):
    frames = moving_square((1, 1), frames=7)
    write_video(tmp_path / "a.avi", frames)
    decoded = decode_video(tmp_path / "a.avi")
    assert len(decoded) == 7 and decoded[0].shape == frames[0].shape
    assert np.abs(decoded[3].astype(int) - frames[3]).mean() < 12  # lossy, but the same picture


@pytest.mark.parametrize("kind", ["actor", "motion", "actor+motion"])
def test_held_out_splits_share_no_group_with_training(kind):
    clips = motion_clips(6, 20).clips
    split = make_split(clips, kind, seed=4)
    for group in kind.split("+"):
        train = {m for i in split.train for m in clips[i].groups[group]}
        test = {m for i in split.test for m in clips[i].groups[group]}
        assert not train & test
        assert set(split.held_out[group]) >= test
    if kind == "motion":  # every class keeps motions on both sides
        assert {clips[i].label for i in split.test} == {clips[i].label for i in split.train} == set(range(6))
    assert len(split.train) + len(split.test) + split.dropped == len(clips)
    assert make_split(clips, kind, seed=4) == split
    assert make_split(clips, kind, seed=5) != split


def test_a_motion_shared_between_actions_is_never_the_last_one_an_action_keeps():
    """θ shares base motions between actions: a motion held out for one label is held out
    for every label showing it, so no label may lose its last training motion so."""
    shared = ("walk_a", "walk_b")  # walk's motions, and the only ones walk_the_line has
    motions = {0: (*shared, "walk_c", "walk_d"), 1: shared, 2: ("hop_a", "hop_b", "hop_c")}
    clips = [_clip(f"v{label}{m}{r}", label, (f"m{r}",), (m,)) for label, ms in motions.items()
             for m in ms for r in range(3)]  # fmt: skip
    for seed in range(40):
        split = make_split(clips, "motion", seed=seed, test_fraction=0.5)
        assert {clips[i].label for i in split.train} == {0, 1, 2}, seed
        assert {clips[i].label for i in split.test} >= {0, 2}, seed


def _clip(key: str, label: int, actor: tuple[str, ...], motion: tuple[str, ...], background=()) -> Clip:
    rgb, flow = np.zeros((1, 2, 2, 3), np.uint8), np.zeros((1, 2, 2, 2), np.float16)
    return Clip(key, label, "virtual", rgb, flow, {"actor": actor, "motion": motion, "background": background})


def test_partners_and_blended_motions_never_train_when_held_out_and_background_people_are_counted():
    # 10 protagonists; each clip's partner and background people are other protagonists
    clips = [_clip(f"v{i:06d}", i % 3, (f"m{i % 10}",) + ((f"m{(i + 3) % 10}",) if i % 2 else ()),
                   (f"base{i % 4}",) + ((f"base{(i + 1) % 4}",) if i % 3 == 0 else ()), (f"m{(i + 5) % 10}",))
             for i in range(60)]  # fmt: skip
    for seed in range(5):
        split = make_split(clips, "actor", seed=seed)
        held = set(split.held_out["actor"])
        assert not {m for i in split.train for m in clips[i].groups["actor"]} & held
        assert all(clips[i].groups["actor"][0] in held for i in split.test)
        # a test clip's partner that also trains is reported apart
        trained = {m for i in split.train for m in clips[i].groups["actor"]}
        assert split.mixed == [i for i in split.test if set(clips[i].groups["actor"][1:]) & trained]
        assert split.background_seen == [i for i in split.train if set(clips[i].groups["background"]) & held]
        assert split.background_seen and split.background_dropped == 0
        excluded = make_split(clips, "actor", seed=seed, background="exclude")
        assert excluded.test == split.test and excluded.background_dropped == len(split.background_seen)
        assert set(excluded.train) == set(split.train) - set(split.background_seen)
        motion = make_split(clips, "motion", seed=seed)
        held = set(motion.held_out["motion"])
        assert not {m for i in motion.train for m in clips[i].groups["motion"]} & held  # blended ones too
        assert any(set(clips[i].groups["motion"][1:]) & held for i in range(60) if i not in motion.test)


def test_on_a_generated_set_no_training_clip_has_a_held_out_performer(phav):
    clips = load_phav(phav, size=(17, 13)).clips
    cases = set()
    for seed in range(12):
        split = make_split(clips, "actor", seed=seed)
        held = set(split.held_out["actor"])
        for i in split.train:
            assert not set(clips[i].groups["actor"]) & held, (seed, clips[i].key)
        if split.dropped:
            cases.add("held-out partner: not trained")
        if split.mixed:
            cases.add("seen partner: tested apart")
        if split.background_seen:
            cases.add("held-out model in the background: counted")
    assert len(cases) == 3, cases  # the set's roles cross (helpers.tiny_phav)


def test_an_action_the_vocabulary_does_not_know_is_a_user_error(phav, tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    edited = tmp_path / "edited"
    shutil.copytree(phav, edited)
    table = pq.read_table(phav / "recipes.parquet")
    actions = ["juggle"] + table.column("action").to_pylist()[1:]
    table = table.set_column(table.column_names.index("action"), "action", pa.array(actions))
    pq.write_table(table.replace_schema_metadata(pq.read_schema(phav / "recipes.parquet").metadata),
                   edited / "recipes.parquet")  # fmt: skip
    for args in (("train", str(edited), "--out", str(tmp_path / "run"), "--epochs", "1"),
                 ("validate!", str(edited), "--checks", "learnability", "--learn-epochs", "1")):  # fmt: skip
        result = invoke_cli(*args)
        assert result.returncode == 2, (args[0], result.stdout, result.stderr)
        message = result.stderr.strip()
        assert "recipes.parquet" in message and "juggle" in message and "Traceback" not in message
        assert len(message.splitlines()) == 1, message


def test_random_split_is_80_20_and_seeded():
    clips = motion_clips(5, 20).clips
    a = make_split(clips, "random", seed=0)
    assert len(a.test) == 20 and len(a.train) == 80 and not set(a.train) & set(a.test)
    assert make_split(clips, "random", seed=0) == a and make_split(clips, "random", seed=1) != a


def test_bad_split_names_the_option():
    with pytest.raises(PhavUserError) as e:
        make_split(motion_clips(2, 2).clips, "weather", seed=0)
    assert e.value.field == "--split" and "actor+motion" in e.value.detail


def test_flow_estimators_farneback_and_a_clear_error_without_tvl1():
    import cv2

    from phav_validators.learn.data import estimate_flow

    frames = list(moving_square((2, 0), frames=4))
    flows = estimate_flow(frames, "farneback")
    assert len(flows) == 4 and flows[0].shape == (48, 64, 2)
    assert flows[0][..., 0].mean() > 0.05  # the square moves right
    if hasattr(cv2, "optflow"):  # opencv-contrib installed: TV-L1 runs
        assert len(estimate_flow(frames, "tvl1")) == 4
    else:
        with pytest.raises(PhavUserError, match="opencv-contrib"):
            estimate_flow(frames, "tvl1")
    with pytest.raises(PhavUserError, match="farneback or tvl1"):
        estimate_flow(frames, "raft")


def test_a_dataset_split_from_the_recipes_alone_is_the_checks_split(phav):
    """dataset_split reads no pixels and gives the ids the check and phav train split into,
    so that a user's PhavClips trains and tests on the same videos."""
    clips = load_phav(phav, size=(17, 13)).clips
    for kind in ("actor", "random"):
        for seed in range(3):
            split = make_split(clips, kind, seed=seed)
            train, test = dataset_split(phav, kind, seed=seed)
            assert train == [clips[i].key for i in split.train] and test == [clips[i].key for i in split.test]
    pytest.importorskip("torch")
    from phav_spec.torchdata import PhavClips

    assert PhavClips(phav, videos=test, segments=2).videos == sorted(test)
