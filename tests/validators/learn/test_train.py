"""Training: deterministic, resumable, mixed-source batches in the configured ratio, and a
learnable signal is learnt (a shuffled one is not)."""

from __future__ import annotations

import dataclasses
import threading
from pathlib import Path

import numpy as np
import pytest
import torch

from phav_spec.errors import PhavUserError
from phav_validators.learn.data import Clip, load_phav, load_real, ucf101_split
from phav_validators.learn.learnability import (
    DISTILLED_RGB_EPOCH,
    LearnOptions,
    binomial_p,
    chance_level,
    epoch_cost,
    learnability_check,
    run_learnability,
)
from phav_validators.learn.train import (
    JITTER_SCALES,
    RECOMMENDED,
    MixedBatches,
    Teacher,
    TrainConfig,
    _fingerprint,
    cut_clip,
    cutting,
    default_precision,
    draw_cut,
    predict,
    recommended_config,
    snippet_starts,
    snippets,
    snippets_and_targets,
    stream_order,
    torch_device,
    train,
)
from tests.validators.learn.helpers import motion_clips, moving_square_clips, ucf101_folder

SMALL = TrainConfig(stream="flow", widths=(8, 16), epochs=2, mix=(("virtual", 8),), threads=1, lr=0.05)


def _weights(model) -> dict[str, torch.Tensor]:
    return {k: v.clone() for k, v in model.state_dict().items()}


def test_snippet_starts_cover_every_segment():
    assert snippet_starts(30, 3, 1, rng=None) == [5, 15, 25]
    rng = np.random.Generator(np.random.PCG64(0))
    for _ in range(50):
        starts = snippet_starts(30, 3, 5, rng=rng)
        assert all(int(k * 26 / 3) <= s < (k + 1) * 26 / 3 for k, s in enumerate(starts))
    assert snippet_starts(2, 3, 5, rng=None) == [0, 0, 0]  # shorter than a snippet


def test_flow_snippets_stack_five_frames_and_flip_negates_u():
    clip = motion_clips(1, 1, frames=12).clips[0]
    clip.flow[...] = 0.0  # most of the frame still (its median vector: none)
    clip.flow[:, 8:16, 4:12] = (1.0, 0.5)  # a mover left of centre
    config = dataclasses.replace(SMALL, crop=1.0)
    x = snippets(clip, config, rng=None)
    assert x.shape == (3, 10, 24, 32)
    bound = 20.0 * 32 / 340
    assert np.allclose(x[:, 0::2, 8:16, 4:12], 4.0 / bound) and np.allclose(x[:, 1::2, 8:16, 4:12], 2.0 / bound)
    flips = [snippets(clip, config, rng=np.random.Generator(np.random.PCG64(s))) for s in range(8)]
    signs = {float(np.sign(f[:, 0::2].sum())) for f in flips}
    assert signs == {1.0, -1.0}  # some flipped (u negated), some not
    for f in flips:
        mover = f[:, :, 8:16, 4:12] if f[:, 0::2].sum() > 0 else f[:, :, 8:16, 20:28]  # mirrored
        assert np.allclose(mover[:, 1::2], 2.0 / bound)  # v kept


def test_flow_centring_removes_camera_motion_and_keeps_the_mover():
    clip = motion_clips(1, 1, frames=12).clips[0]
    clip.flow[...] = (0.8, -0.4)  # the camera pans: every pixel moves alike
    clip.flow[:, 8:12, 10:14] = (1.8, -0.4)  # a small mover on top of the pan
    x = snippets(clip, dataclasses.replace(SMALL, crop=1.0), rng=None)
    bound = 20.0 * 32 / 340
    assert np.allclose(x[:, :, :8], 0.0) and np.allclose(x[:, :, 12:], 0.0)
    assert np.allclose(x[:, 0::2, 8:12, 10:14], 1.0 * 4.0 / bound, atol=1e-2)
    assert np.allclose(x[:, 1::2, 8:12, 10:14], 0.0, atol=1e-2)


@pytest.mark.parametrize("scale_jitter", [False, True], ids=["fixed-crop", "multi-scale"])
def test_training_is_deterministic_for_a_seed(scale_jitter):
    data = motion_clips(3, 6)
    config = dataclasses.replace(SMALL, scale_jitter=scale_jitter)
    a = train({"virtual": data.clips}, {"virtual": 3}, config)
    b = train({"virtual": data.clips}, {"virtual": 3}, config)
    c = train({"virtual": data.clips}, {"virtual": 3}, dataclasses.replace(config, seed=1))
    wa, wb, wc = _weights(a.model), _weights(b.model), _weights(c.model)
    assert all(torch.equal(wa[k], wb[k]) for k in wa)
    assert not all(torch.equal(wa[k], wc[k]) for k in wa)


def test_an_interrupted_run_resumes_to_the_uninterrupted_weights(tmp_path):
    data = motion_clips(3, 6)
    config = dataclasses.replace(SMALL, epochs=3)
    whole = train({"virtual": data.clips}, {"virtual": 3}, config)

    def stop_after_two(epoch, total):
        if epoch.epoch == 2:
            raise KeyboardInterrupt

    ckpt = tmp_path / "flow.pt"
    with pytest.raises(KeyboardInterrupt):
        train({"virtual": data.clips}, {"virtual": 3}, config, checkpoint=ckpt, progress=stop_after_two)
    assert ckpt.exists() and not list(tmp_path.glob(".*.tmp"))
    resumed = train({"virtual": data.clips}, {"virtual": 3}, config, checkpoint=ckpt)
    assert resumed.resumed_from == 2 and len(resumed.history) == 3
    ww, wr = _weights(whole.model), _weights(resumed.model)
    assert all(torch.equal(ww[k], wr[k]) for k in ww)
    # a finished checkpoint trains nothing more; other settings refuse it
    again = train({"virtual": data.clips}, {"virtual": 3}, config, checkpoint=ckpt)
    assert again.resumed_from == 3
    with pytest.raises(PhavUserError, match="other settings"):
        train({"virtual": data.clips}, {"virtual": 3}, dataclasses.replace(config, lr=0.1), checkpoint=ckpt)


def test_a_distilled_stream_begun_against_a_teacher_that_trained_on_starts_again(tmp_path):
    """The budget stopped the flow stream, the RGB stream distilled from it; rerun with more
    time, the flow stream trains on and the RGB stream starts again against the finished
    teacher, as an uninterrupted run does (its checkpoint used to be refused)."""
    data = {"virtual": motion_clips(3, 6).clips}
    flow = dataclasses.replace(SMALL, epochs=2)
    rgb = TrainConfig(stream="rgb", widths=(8, 16), epochs=2, mix=(("virtual", 8),), threads=1, lr=0.05,
                      distill=1.0)  # fmt: skip
    early = train(data, {"virtual": 3}, dataclasses.replace(flow, epochs=1))
    ckpt = tmp_path / "rgb.pt"
    train(data, {"virtual": 3}, rgb, checkpoint=ckpt, teacher=Teacher(early.model, early.config))
    finished = train(data, {"virtual": 3}, flow)
    teacher = Teacher(finished.model, finished.config)
    again = train(data, {"virtual": 3}, rgb, checkpoint=ckpt, teacher=teacher)
    whole = train(data, {"virtual": 3}, rgb, teacher=teacher)
    assert again.resumed_from == 0 and len(again.history) == 2
    wa, ww = _weights(again.model), _weights(whole.model)
    assert all(torch.equal(wa[k], ww[k]) for k in ww)
    with pytest.raises(PhavUserError, match="other settings"):  # another config is still refused
        train(data, {"virtual": 3}, dataclasses.replace(rgb, lr=0.1), checkpoint=ckpt, teacher=teacher)


def test_a_checkpoint_fingerprint_leaves_out_the_settings_at_their_defaults():
    """A setting added later (at its default) does not orphan a checkpoint made before it."""
    data = {"virtual": motion_clips(3, 2).clips}
    config = dataclasses.replace(SMALL, lr=0.1)
    assert config.changed() == {"widths": [8, 16], "epochs": 2, "mix": [["virtual", 8]], "lr": 0.1}
    print_ = _fingerprint(config, data, {"virtual": 3}, None)
    assert print_ == _fingerprint(dataclasses.replace(config, diff_gain=1.0), data, {"virtual": 3}, None)
    assert print_ != _fingerprint(dataclasses.replace(config, lr=0.05), data, {"virtual": 3}, None)
    # Any frame's pixels or flow, not only a clip's first RGB and last flow frame.
    for modality in ("rgb", "flow"):
        clips = [dataclasses.replace(c) for c in data["virtual"]]
        changed = getattr(clips[0], modality).copy()
        changed[1] += 1
        clips[0] = dataclasses.replace(clips[0], **{modality: changed})
        assert print_ != _fingerprint(config, {"virtual": clips}, {"virtual": 3}, None), modality


def test_a_damaged_checkpoint_is_a_user_error(tmp_path):
    ckpt = tmp_path / "flow.pt"
    ckpt.write_bytes(b"not a checkpoint")
    data = motion_clips(2, 2)
    with pytest.raises(PhavUserError, match="not a readable checkpoint"):
        train({"virtual": data.clips}, {"virtual": 2}, SMALL, checkpoint=ckpt)


def test_mixed_batches_hold_every_source_in_the_ratio():
    rng = np.random.Generator(np.random.PCG64(0))
    batches = MixedBatches({"virtual": range(7), "real": range(100, 130)}, [("virtual", 10), ("real", 22)], rng=rng)
    seen_virtual = []
    for _ in range(20):
        batch = batches.next()
        assert len(batch) == 32
        assert sum(s == "virtual" for s, _ in batch) == 10 and sum(s == "real" for s, _ in batch) == 22
        seen_virtual += [i for s, i in batch if s == "virtual"]
    # without replacement within a pass: after 200 draws every virtual clip came up 28-29 times
    counts = np.bincount(seen_virtual, minlength=7)
    assert counts.min() >= 28 and counts.max() <= 29


def test_cool_tsn_both_heads_losses_fall_on_a_mixed_batch(phav, tmp_path):
    """Cool-TSN on a generated UCF-101 folder (real) mixed 10 : 22 with PHAV clips
    (virtual): both sources' losses fall, and every batch trained on holds both in the
    configured ratio."""
    virtual = load_phav(phav, size=(32, 24))
    official = ucf101_split(ucf101_folder(tmp_path), 1)
    real = load_real(official.train, size=(32, 24))
    config = TrainConfig(stream="flow", widths=(8, 16), epochs=30, mix=(("virtual", 10), ("real", 22)), lr=0.05)
    seen = []
    original = MixedBatches.next

    def spy(self):
        batch = original(self)
        seen.append((sum(s == "virtual" for s, _ in batch), sum(s == "real" for s, _ in batch)))
        return batch

    MixedBatches.next = spy
    try:
        heads = {"virtual": len(virtual.classes), "real": len(official.classes)}
        result = train({"virtual": virtual.clips, "real": real}, heads, config)
    finally:
        MixedBatches.next = original
    assert len(seen) == 30 and set(seen) == {(10, 22)}
    first, last = result.history[0].losses, result.history[-1].losses
    assert last["virtual"] < 0.8 * first["virtual"], (first, last)
    assert last["real"] < 0.8 * first["real"], (first, last)
    probs = predict(result.model, real, config, "real")
    assert probs.shape == (len(real), 3) and np.allclose(probs.sum(1), 1.0, atol=1e-5)


def test_learnable_motion_passes_and_shuffled_labels_do_not():
    clips = motion_clips(6, 20)
    opts = LearnOptions(epochs=15, budget_minutes=5, threads=1, streams=("flow",))
    result = run_learnability(clips, opts)
    assert result.accuracy() > 0.8 and result.p_value < 1e-6, (result.accuracy(), result.p_value)
    control = run_learnability(clips, dataclasses.replace(opts, shuffle_labels=True))
    assert control.accuracy() < 0.5 and control.p_value > 1e-3, (control.accuracy(), control.p_value)


def test_the_budget_is_shared_by_each_streams_expected_seconds(monkeypatch):
    """The distilled RGB stream's epoch costs 1.5 flow epochs, so 30 flow + 10 RGB epochs
    share 45 flow epochs' time: flow 30/45 of the budget, RGB what flow left."""
    import phav_validators.learn.learnability as learnability

    budgets, spent = {}, {}
    real = learnability.train

    def recording(data, heads, config, **kwargs):  # one epoch each: the shares are what is tested
        budgets[config.stream] = kwargs["max_seconds"]
        result = real(data, heads, dataclasses.replace(config, epochs=1), **kwargs)
        spent[config.stream] = result.seconds
        return result

    monkeypatch.setattr(learnability, "train", recording)
    run_learnability(motion_clips(3, 4), LearnOptions(epochs=30, rgb_epochs=10, budget_minutes=3, threads=1))
    assert budgets["flow"] == pytest.approx(180 * 30 / 45)
    assert budgets["rgb"] == pytest.approx(180 - spent["flow"])
    rgb_epochs = RECOMMENDED.rgb_epochs
    assert epoch_cost(recommended_config(["rgb", "flow"]).for_stream("rgb")) == rgb_epochs * DISTILLED_RGB_EPOCH
    assert epoch_cost(recommended_config(["rgb"]).for_stream("rgb")) == rgb_epochs  # no teacher, no teacher's cost


def test_a_stop_at_the_budget_says_what_it_cost_and_what_would_finish():
    """A budget far too small for the schedules: the flow stream gets the epoch it starts
    with, the RGB stream none (its epoch time is then estimated by ``epoch_cost``), and the
    note names the epochs reached and the minutes the schedules would need here."""
    result = run_learnability(motion_clips(3, 4), LearnOptions(epochs=6, rgb_epochs=3, budget_minutes=1e-4, threads=1))
    assert result.stopped_on_time and result.epochs == {"flow": 1, "rgb": 0}
    assert result.schedule == {"flow": 6, "rgb": 3}
    assert result.epoch_seconds["flow"] > 0
    assert result.epoch_seconds["rgb"] == pytest.approx(result.epoch_seconds["flow"] * DISTILLED_RGB_EPOCH)
    assert result.full_minutes() > result.minutes  # six and three epochs cost more than the one
    note = result.budget_note(1e-4)
    assert "flow 1 of 6 epochs, rgb 0 of 3 epochs" in note
    assert f"--learn-minutes {result.minutes_needed()}" in note
    assert "--learn-stem-pool" not in note  # the default already pools
    result.settings["stem_pool"] = False  # a run that turned it off is pointed back at it
    assert "--learn-stem-pool (the default)" in result.budget_note(1e-4)


def test_the_check_pools_the_stem_of_both_streams_unless_asked_not_to():
    base = LearnOptions().config(threads=1)
    assert base.for_stream("flow").arch.stem_pool and base.for_stream("rgb").arch.stem_pool
    assert not LearnOptions(stem_pool=False).config(threads=1).for_stream("flow").arch.stem_pool


@pytest.mark.parametrize(("precision", "channels_last"), [("fp32", True), ("bf16", False)])
def test_float32_trains_channels_last_and_bfloat16_in_the_default_layout(precision, channels_last):
    config = dataclasses.replace(SMALL, precision=precision)
    result = train({"virtual": motion_clips(3, 2).clips}, {"virtual": 3}, dataclasses.replace(config, epochs=1))
    stem = result.model.backbone.features[0].weight
    assert stem.is_contiguous(memory_format=torch.channels_last) == channels_last


def test_chance_is_uniform_guessing_or_the_agreement_of_the_marginals():
    labels = np.array([0, 0, 0, 1])
    assert chance_level(labels, np.array([0, 0, 0, 0]), 35) == pytest.approx(3 / 4)  # always the majority
    assert chance_level(labels, np.array([1, 1, 1, 1]), 35) == pytest.approx(1 / 4)
    assert chance_level(labels, np.array([5, 6, 7, 8]), 35) == pytest.approx(1 / 35)  # never below uniform
    assert chance_level(np.arange(35), np.arange(35)[::-1], 35) == pytest.approx(1 / 35)
    assert binomial_p(0, 10, 0.1) == pytest.approx(1.0)
    assert binomial_p(10, 10, 0.5) == pytest.approx(0.5**10)


class _Payload:
    """An object whose unpickling would run code (``__reduce__``): a hostile checkpoint."""

    def __reduce__(self):
        return (print, ("code ran while loading a checkpoint",))


def test_a_checkpoint_that_would_run_code_is_refused(tmp_path):
    ckpt = tmp_path / "flow.pt"
    torch.save({"format": "phav-tsn-1", "payload": _Payload()}, ckpt)
    data = motion_clips(2, 2)
    with pytest.raises(PhavUserError, match="not a readable checkpoint"):
        train({"virtual": data.clips}, {"virtual": 2}, SMALL, checkpoint=ckpt)


def test_rgb_snippets_stack_consecutive_frames():
    clip = moving_square_clips(1, 1, frames=12).clips[0]
    config = dataclasses.replace(SMALL, stream="rgb", rgb_frames=3, crop=1.0)
    x = snippets(clip, config, rng=None)
    assert x.shape == (3, 9, 24, 32)
    starts = snippet_starts(12, 3, 3, rng=None)
    for k, s in enumerate(starts):
        for i in range(3):
            expected = (clip.rgb[s + i].astype(np.float32) / 255.0 - 0.45) / 0.225
            assert np.allclose(x[k, 3 * i : 3 * i + 3], expected.transpose(2, 0, 1), atol=1e-6)


def test_rgb_difference_input_is_the_first_frame_then_consecutive_differences():
    clip = moving_square_clips(1, 1, frames=12).clips[0]
    config = dataclasses.replace(SMALL, stream="rgb", rgb_frames=3, crop=1.0)
    stacked = snippets(clip, config, rng=None).reshape(3, 3, 3, 24, 32)
    diff = snippets(clip, dataclasses.replace(config, rgb_diff=True), rng=None).reshape(3, 3, 3, 24, 32)
    assert np.array_equal(diff[:, 0], stacked[:, 0])
    assert np.allclose(diff[:, 1:], stacked[:, 1:] - stacked[:, :-1], atol=1e-6)
    assert np.abs(diff[:, 1:]).max() > 1.0  # the square moved
    for bad in (dataclasses.replace(config, rgb_frames=1), dataclasses.replace(config, stream="flow")):
        with pytest.raises(PhavUserError) as e:
            dataclasses.replace(bad, rgb_diff=True)
        assert e.value.field == "--rgb-diff"
    assert TrainConfig(stream="rgb", rgb_frames=3, rgb_diff=True).for_stream("flow").rgb_diff is False
    # a gain scales the differences alone; the first frame stays as it was
    gained = snippets(clip, dataclasses.replace(config, rgb_diff=True, diff_gain=4.0), rng=None)
    gained = gained.reshape(3, 3, 3, 24, 32)
    assert np.array_equal(gained[:, 0], diff[:, 0]) and np.allclose(gained[:, 1:], 4.0 * diff[:, 1:], atol=1e-5)
    with pytest.raises(PhavUserError) as e:
        dataclasses.replace(config, diff_gain=0.0)
    assert e.value.field == "--diff-gain"


@pytest.mark.parametrize(("how", "learns"), [({}, False), ({"rgb_frames": 3}, True),
                                             ({"rgb_frames": 3, "rgb_diff": True}, True)])  # fmt: skip
def test_the_rgb_stream_learns_a_motion_no_single_frame_shows(how, learns):
    """A square's direction of travel: TSN's single RGB frame cannot see it; stacked frames,
    as they are or as differences, can."""
    data = moving_square_clips(3, 24, seed=1)
    test = moving_square_clips(3, 8, seed=2)
    config = dataclasses.replace(SMALL, **{"stream": "rgb", "epochs": 25, "widths": (16, 32), "dropout": 0.0, **how})
    result = train({"virtual": data.clips}, {"virtual": 3}, config)
    probs = predict(result.model, test.clips, config, "virtual")
    accuracy = float((probs.argmax(1) == np.array([c.label for c in test.clips])).mean())
    assert (accuracy > 0.85) if learns else (accuracy < 0.5), accuracy


def test_the_teachers_flow_follows_the_students_crop_and_flip():
    rng = np.random.Generator(np.random.PCG64(3))
    still = rng.integers(0, 256, (1, 24, 32, 3), dtype=np.uint8).repeat(10, axis=0)
    flow = np.zeros((10, 24, 32, 2), np.float16)
    flow[:, :, 20:, 0] = 0.5  # the right side moves right
    clip = Clip("c", 0, "virtual", still, flow, {})
    config = dataclasses.replace(SMALL, stream="rgb", rgb_frames=3, crop=1.0)
    x, targets = snippets_and_targets(clip, config, rng=None, teacher=SMALL)
    assert x.shape == (3, 9, 24, 32) and targets["teacher"].shape == (3, 10, 24, 32)
    assert targets["teacher"][:, 0::2, :, 20:].min() > 0 and not targets["teacher"][:, :, :, :20].any()
    seen = {}
    for s in range(12):
        xs, ts = snippets_and_targets(clip, config, rng=np.random.Generator(np.random.PCG64(s)), teacher=SMALL)
        seen[bool(np.array_equal(xs, x))] = (xs, ts)
    xf, tf = seen[False]  # a flipped draw: everything mirrored, u negated
    assert np.allclose(xf, x[..., ::-1])
    assert np.allclose(tf["teacher"][:, 0::2], -targets["teacher"][:, 0::2, :, ::-1])
    assert np.allclose(tf["teacher"][:, 1::2], targets["teacher"][:, 1::2, :, ::-1])


def test_scale_jitter_crops_at_tsns_scales_and_scales_the_flow_with_the_frame():
    clip = motion_clips(1, 1, frames=12, size=(64, 48)).clips[0]
    clip.flow[...] = 0.0
    clip.flow[:, 16:32, 22:42] = (1.0, 0.5)  # a mover inside every crop (at least 2/3 of each side)
    config = dataclasses.replace(SMALL, scale_jitter=True)
    plain = snippets(clip, dataclasses.replace(config, scale_jitter=False), rng=None)
    assert np.array_equal(snippets(clip, config, rng=None), plain)  # testing: the centre crop
    bound = 20.0 * 64 / 340
    widths, heights = set(), set()
    for s in range(40):
        x = snippets(clip, config, rng=np.random.Generator(np.random.PCG64(s)))
        assert x.shape == plain.shape == (3, 10, 42, 56)
        u, v = float(np.abs(x[:, 0::2]).max()), float(x[:, 1::2].max())  # inside the mover
        # a crop w' px wide seen at 56 px magnifies motion 56 / w': u = 4/bound · 56/w'
        widths.add(round(4.0 / bound * 56 / u))
        heights.add(round(2.0 / bound * 42 / v))
    assert widths == {round(64 * s) for s in JITTER_SCALES}
    assert heights == {round(48 * s) for s in JITTER_SCALES}


def test_scale_jitter_resizes_the_teachers_flow_with_the_input():
    clip = moving_square_clips(1, 1, frames=10).clips[0]
    config = dataclasses.replace(SMALL, stream="rgb", rgb_frames=3, scale_jitter=True)
    for s in range(10):
        x, targets = snippets_and_targets(clip, config, rng=np.random.Generator(np.random.PCG64(s)), teacher=SMALL)
        assert x.shape == (3, 9, 21, 28) and targets["teacher"].shape == (3, 10, 21, 28)


def test_a_batch_cut_in_threads_is_the_batch_cut_in_turn():
    clips = _square_clips_with_flow(1)[:16]
    rgb = dataclasses.replace(SMALL, stream="rgb", rgb_frames=3, rgb_diff=True, scale_jitter=True)
    teacher = SMALL
    rng = np.random.Generator(np.random.PCG64(5))
    in_turn = [snippets_and_targets(c, rgb, rng=rng, teacher=teacher) for c in clips]
    rng = np.random.Generator(np.random.PCG64(5))
    places = [draw_cut(c, rgb, rng=rng) for c in clips]  # every random draw first, in order
    with cutting(torch.device("cuda"), 4) as cutter:  # off the CPU the cores are free: a thread pool
        jobs = [(c, rgb, where) for c, where in zip(clips, places, strict=True)]
        threaded = cutter(lambda job: cut_clip(*job, teacher=teacher), jobs)
        names = set(cutter(lambda _: threading.current_thread().name, range(16)))
    assert all(n.startswith("phav-cut") for n in names)
    for (x, t), (y, u) in zip(in_turn, threaded, strict=True):
        assert np.array_equal(x, y) and t.keys() == u.keys() == {"teacher"}
        assert all(np.array_equal(t[k], u[k]) for k in t)
    assert len({p.flip for p in places}) == 2 and len({p.starts for p in places}) > 1
    with cutting(torch.device("cpu"), 4) as cutter:  # torch's threads fill the cores: in turn
        assert set(cutter(lambda _: threading.current_thread().name, range(4))) == {threading.main_thread().name}


def _square_clips_with_flow(seed: int) -> list[Clip]:
    """Moving squares whose flow is the square's own motion (a flow stream can learn it)."""
    data = moving_square_clips(3, 12, seed=seed)
    out = []
    for c in data.clips:
        flow = np.zeros(c.flow.shape, np.float32)
        square = c.rgb[..., 0] == 255
        angle = np.pi * (c.label + 0.5) / 3 - np.pi / 2
        flow[square] = (1.5 * np.cos(angle), 1.5 * np.sin(angle))
        out.append(dataclasses.replace(c, flow=flow.astype(np.float16)))
    return out


def test_distillation_pulls_the_rgb_features_towards_the_flow_teachers():
    clips = _square_clips_with_flow(1)
    flow_config = dataclasses.replace(SMALL, epochs=4, widths=(8, 16))
    teacher = Teacher(train({"virtual": clips}, {"virtual": 3}, flow_config).model, flow_config)
    student = dataclasses.replace(SMALL, stream="rgb", rgb_frames=3, distill=5.0, epochs=6, widths=(8, 16))
    result = train({"virtual": clips}, {"virtual": 3}, student, teacher=teacher)
    untrained = train({"virtual": clips}, {"virtual": 3}, dataclasses.replace(student, epochs=1), teacher=teacher)

    def distance(model) -> float:
        pairs = [snippets_and_targets(c, student, rng=None, teacher=flow_config) for c in clips[:16]]
        model.eval()
        with torch.no_grad():
            _, more = model(torch.from_numpy(np.stack([p[0] for p in pairs])), extras=True)
        return float(teacher.loss(more["features"], [p[1] for p in pairs]))

    assert distance(result.model) < 0.7 * distance(untrained.model)
    with pytest.raises(PhavUserError, match="distillation"):
        train({"virtual": clips}, {"virtual": 3}, student)  # a weight but no teacher
    with pytest.raises(PhavUserError) as e:
        TrainConfig(stream="flow", distill=1.0)
    assert e.value.field == "--distill"


def test_the_flow_stream_trains_first_only_when_it_teaches():
    plain, distilling = TrainConfig(stream="rgb"), TrainConfig(stream="rgb", distill=5.0)
    assert stream_order(["rgb", "flow"], plain) == ["rgb", "flow"]
    assert stream_order(["rgb", "flow"], distilling) == ["flow", "rgb"]
    assert stream_order(["flow"], distilling) == ["flow"]
    with pytest.raises(PhavUserError) as e:
        stream_order(["rgb"], distilling)
    assert e.value.field == "--distill"


def test_bf16_training_is_deterministic_and_learns_like_fp32():
    data = motion_clips(3, 6)
    config = dataclasses.replace(SMALL, precision="bf16", epochs=15)
    a = train({"virtual": data.clips}, {"virtual": 3}, config)
    b = train({"virtual": data.clips}, {"virtual": 3}, config)
    wa, wb = _weights(a.model), _weights(b.model)
    assert all(torch.equal(wa[k], wb[k]) for k in wa)
    assert all(v.dtype != torch.bfloat16 for v in wa.values())  # weights stay float32; autocast is the arithmetic
    fp32 = train({"virtual": data.clips}, {"virtual": 3}, dataclasses.replace(config, precision="fp32"))
    assert not all(torch.equal(wa[k], v) for k, v in _weights(fp32.model).items())  # another arithmetic
    # … that learns the same: the loss falls to within 5 % of float32's, every clip fitted
    assert a.history[-1].losses["virtual"] < 0.5 * a.history[0].losses["virtual"]
    assert (
        abs(a.history[-1].losses["virtual"] - fp32.history[-1].losses["virtual"])
        < 0.05 * fp32.history[-1].losses["virtual"]
    )
    assert a.history[-1].train_accuracy == fp32.history[-1].train_accuracy == 1.0
    probs = predict(a.model, data.clips, config, "virtual")
    assert probs.dtype == np.float32 and np.allclose(probs.sum(1), 1.0, atol=1e-5)
    with pytest.raises(PhavUserError) as e:
        TrainConfig(precision="fp16")
    assert e.value.field == "--precision"


def test_the_rgb_stream_takes_its_own_epochs():
    config = TrainConfig(stream="rgb", epochs=80, rgb_epochs=40, rgb_frames=5, rgb_diff=True)
    assert config.for_stream("rgb").epochs == 40 and config.for_stream("flow").epochs == 80
    assert TrainConfig(stream="rgb", epochs=80).for_stream("rgb").epochs == 80  # None: the same epochs
    assert config.for_stream("flow").rgb_frames == 1  # the RGB-only settings leave the flow stream


@pytest.mark.parametrize(
    ("vendor", "flags", "expected"),
    [
        ("GenuineIntel", {"avx512_bf16", "amx_bf16", "amx_tile"}, "bf16"),
        ("GenuineIntel", {"avx512f", "avx512_bf16"}, "fp32"),
        ("AuthenticAMD", {"avx512f", "avx512_bf16"}, "bf16"),
        ("AuthenticAMD", {"avx2"}, "fp32"),
        ("", set(), "fp32"),
    ],
)
def test_bfloat16_is_the_cpu_default_where_it_was_measured_faster(monkeypatch, vendor, flags, expected):
    """AVX-512 BF16 made a training step slower than float32 on a Xeon without AMX and
    faster on an AMD EPYC (docs/experiments/learnability.md, "On a CPU without AMX" and "On an
    AMD EPYC")."""
    import phav_validators.learn.train as train_module

    monkeypatch.setattr(train_module, "_cpu_info", lambda: (vendor, flags))
    assert default_precision("cpu") == expected


def test_the_stem_is_pooled_by_default_on_a_cpu_and_not_on_a_gpu(monkeypatch):
    """Time binds on a CPU, accuracy on a GPU, where the unpooled network scored better
    (docs/experiments/learnability.md, "On a GPU"); CUDA is pretended here, so only the
    settings are built, nothing runs on it."""
    assert recommended_config(["rgb", "flow"]).stem_pool and RECOMMENDED.stem_pool
    monkeypatch.setattr(torch.cuda, "is_available", lambda: True)
    monkeypatch.setattr(torch.cuda, "device_count", lambda: 1)
    monkeypatch.setattr(torch.cuda, "is_bf16_supported", lambda: True)
    on_gpu = recommended_config(["rgb", "flow"], device="cuda")
    assert not on_gpu.stem_pool and not on_gpu.for_stream("flow").arch.stem_pool and on_gpu.precision == "bf16"
    assert recommended_config(["rgb", "flow"], device="cuda:0", stem_pool=True).stem_pool  # unless asked


@pytest.mark.parametrize(
    ("name", "gpus", "error"),
    [("cpu", 0, None), ("cuda:0", 1, None), ("cuda", 0, "CUDA is not available"), ("cuda:1", 1, "no GPU 'cuda:1'"),
     ("mps", 0, "choose cpu, cuda or cuda:N"), ("cpu:0", 0, "choose"), ("gpu", 1, "choose")],
)  # fmt: skip
def test_a_device_is_the_cpu_or_a_cuda_gpu_this_machine_has(monkeypatch, name, gpus, error):
    """torch names more devices (mps, xpu, ...) than training supports and tests; any other
    name, or a GPU this machine lacks, is a user error before anything runs (CUDA is
    pretended here: only the device is built)."""
    monkeypatch.setattr(torch.cuda, "is_available", lambda: gpus > 0)
    monkeypatch.setattr(torch.cuda, "device_count", lambda: gpus)
    if error is None:
        assert str(torch_device(name)) == name
        return
    with pytest.raises(PhavUserError, match=error) as e:
        torch_device(name)
    assert e.value.field == "--device"


def test_the_recommended_settings_follow_the_streams_trained():
    both = recommended_config(["rgb", "flow"], seed=3)
    assert both.distill == RECOMMENDED.distill > 0 and both.rgb_diff and both.seed == 3
    assert stream_order(["rgb", "flow"], both) == ["flow", "rgb"]
    assert both.precision == default_precision() and both.threads >= 1
    alone = recommended_config(["rgb"])
    assert alone.distill == 0 and alone.rgb_frames == RECOMMENDED.rgb_frames  # no teacher to learn from
    assert stream_order(["rgb"], alone) == ["rgb"]
    flow = recommended_config(["flow"])
    assert flow.stream == "flow" and not flow.rgb_diff and flow.distill == 0
    given = recommended_config(["flow"], rgb_frames=5, diff_gain=12.0, epochs=120)  # as the CLI passes them
    assert given == dataclasses.replace(flow, epochs=120) and given.rgb_frames == 1 and given.rgb_epochs is None
    assert recommended_config(["flow"], precision="fp32").precision == "fp32"
    # other epochs scale the RGB stream's in the recommended proportion, unless given
    assert (
        recommended_config(["rgb", "flow"], epochs=30).rgb_epochs == 30 * RECOMMENDED.rgb_epochs // RECOMMENDED.epochs
    )
    assert recommended_config(["rgb", "flow"], epochs=30, rgb_epochs=7).rgb_epochs == 7
    # RGB differences need 2 or more frames: TSN's single frame turns them off unless asked
    assert not recommended_config(["rgb", "flow"], rgb_frames=1).rgb_diff
    assert recommended_config(["rgb", "flow"], rgb_frames=2).rgb_diff
    # TSN's multi-scale crops, unless turned off
    assert both.scale_jitter and not recommended_config(["flow"], scale_jitter=False).scale_jitter


@pytest.mark.parametrize(("change", "field"), [({"dropout": 1.0}, "--dropout"), ({"widths": (0, 64)}, "--widths")])
def test_the_networks_options_are_checked_with_the_rest_before_any_data(change, field):
    with pytest.raises(PhavUserError) as e:
        TrainConfig(**change)
    assert e.value.field == field


def test_the_verdict_is_on_test_clips_whose_every_performer_is_unseen():
    """A held-out split keeps every performer of a test clip out of training: test clips
    whose partner trained were counted in the verdict; now they are scored apart, and the
    verdict's chance, p-value and accuracy are the other test clips'."""
    clips = motion_clips(3, 10)
    partner = {"actor": ("model_partner",)}  # in every third clip, a partner no clip is played by: never held out
    partnered = [dataclasses.replace(c, groups={**c.groups, "actor": c.groups["actor"] + partner["actor"]})
                 if i % 3 == 0 else c for i, c in enumerate(clips.clips)]  # fmt: skip
    result = run_learnability(dataclasses.replace(clips, clips=partnered),
                              LearnOptions(epochs=2, budget_minutes=1, threads=1, streams=("flow",)))  # fmt: skip
    mixed = result.videos["mixed"]
    assert mixed and not set(mixed) & set(result.keys) and len(result.labels) == len(result.keys)
    assert result.mixed_accuracy is not None and 0.0 <= result.mixed_accuracy <= 1.0
    check = learnability_check(result, LearnOptions(budget_minutes=1), Path("set"))
    assert check.numbers["test_clips"] == len(result.keys) and check.numbers["mixed_test_clips"] == len(mixed)
    assert f"{len(mixed)} more with a partner seen in training, scored apart" in check.summary


def test_where_every_test_clip_is_mixed_the_verdict_is_on_them_and_says_so():
    """A set of a few videos may hold out only a protagonist whose partner trains: no test
    clip has every performer unseen. The verdict is then on the mixed clips, as before, and
    the report says so rather than failing the split."""
    clips = motion_clips(3, 10)
    partner = ("model_partner",)  # every clip's partner: seen wherever a clip trains
    partnered = [dataclasses.replace(c, groups={**c.groups, "actor": c.groups["actor"] + partner}) for c in clips.clips]
    result = run_learnability(dataclasses.replace(clips, clips=partnered),
                              LearnOptions(epochs=1, budget_minutes=1, threads=1, streams=("flow",)))  # fmt: skip
    assert result.mixed_in_verdict and set(result.keys) == set(result.videos["mixed"]) and result.mixed_accuracy is None
    check = learnability_check(result, LearnOptions(budget_minutes=1), Path("set"))
    assert check.numbers["mixed_in_verdict"] and "no clip has every member unseen" in check.summary
