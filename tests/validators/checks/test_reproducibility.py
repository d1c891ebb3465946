"""The reproducibility check: videos regenerated from their recipes against the shards,
frame by frame; the only check that catches a frame changed together with its manifest."""

from __future__ import annotations

import cv2

from phav_spec.manifest import dump_manifest, load_manifest
from phav_validators.checks.reproduce import shard_video_frames
from phav_validators.findings import Reason, Status
from tests.validators.checks.support import (
    assert_fails,
    check,
    png_edit,
    refresh_manifest,
    rewrite_tar,
    shard_of,
    validate,
)


def test_changed_frame_with_updated_manifest_is_caught_by_reproducibility(data):
    def paint(image):
        image[50:60, 50:60] = 255 - image[50:60, 50:60]
        return image

    rewrite_tar(shard_of(data, "v000002"), png_edit("v000002/00003.rgb.png", paint))
    refresh_manifest(data)
    report = validate(data, "integrity", "reproducibility", regenerate=3)
    assert check(report, "integrity").status != Status.FAIL
    hits = assert_fails(report, "reproducibility", Reason.REGENERATION_MISMATCH, video="v000002")
    assert "rgb (frame 00003)" in hits[0].message and "bit-exact" in hits[0].message


def test_frame_reader_skips_images_of_another_size(data):
    """The reproducibility / HTML reader never decodes an image whose header is off-size."""
    shard = shard_of(data, "v000000")
    rewrite_tar(shard, png_edit("v000000/00001.rgb.png", lambda a: cv2.resize(a, (4000, 4000))))
    frames = [f for f, _ in shard_video_frames(shard, "v000000")]
    assert 1 not in frames and frames[:2] == [0, 2]


def test_a_manifest_without_its_renderer_warns_and_compares_within_tolerances(data):
    """Without a renderer of record no pixel is promised bit for bit: the check says so (a
    warning naming the manifest) and compares within the tolerances, not as if the machine's
    renderer differed."""
    m = load_manifest(data / "manifest.json")
    dump_manifest(m.model_copy(update={"renderer": None}), data / "manifest.json")
    result = check(validate(data, "reproducibility", regenerate=1), "reproducibility")
    assert result.status == Status.WARN
    assert [f.reason for f in result.report.findings] == [Reason.RENDERER_UNRECORDED]
    assert result.report.findings[0].file == "manifest.json"
    assert result.numbers["exact"] is False and result.numbers["matched"] == 1
    assert "the manifest records no renderer fingerprint" in result.summary


def test_a_missing_shard_is_integritys_finding_not_a_regeneration_mismatch(data):
    """The videos of a deleted shard regenerate to the manifest's content hashes: the
    integrity check says the shard is missing, reproducibility notes the frames it could not
    compare and blames nothing on the renderer."""
    (data / "phav-000001.tar").unlink()
    report = validate(data, "integrity", "reproducibility", regenerate=3)
    assert_fails(report, "integrity", Reason.MISSING_FILE)
    reproducibility = check(report, "reproducibility")
    assert reproducibility.status == Status.PASS and reproducibility.numbers["matched"] == 3
    assert any("v000002: 6 of 6 frames not in its shard" in n for n in reproducibility.report.notes)
    for shard in data.glob("*.tar"):  # no frame left to read: encoding and consistency checked nothing
        shard.unlink()
    report = validate(data, "integrity", "encoding", "consistency")
    assert [check(report, c).status for c in ("encoding", "consistency")] == [Status.SKIP, Status.SKIP]


def test_under_another_renderer_a_video_without_frames_to_compare_is_not_a_match(data, monkeypatch):
    """Within tolerances (another renderer) there is no content hash to fall back on: a video
    whose shard is gone is not compared, and with none compared the check is skipped."""
    from phav_validators.checks import reproduce

    monkeypatch.setattr(reproduce, "renderer_differences", lambda *args, **kwargs: ["gl_settings"])
    for shard in data.glob("*.tar"):
        shard.unlink()
    result = check(validate(data, "integrity", "reproducibility", regenerate=1), "reproducibility")
    assert result.status == Status.SKIP and "no regenerated video's frames are in the shards" in result.summary


def test_beyond_tolerances_fails_under_another_driver_and_warns_where_the_motion_may_differ(data):
    """A frame drawn otherwise (its hashes with it): where only the GL driver differs, the
    scene is the same and a video beyond the tolerances fails; where numpy's or OpenBLAS's
    kernels differ, the physics can take a video another way, and it is a warning naming them."""
    rewrite_tar(shard_of(data, "v000001"), png_edit("v000001/00002.rgb.png", lambda image: 255 - image))
    refresh_manifest(data)
    m = load_manifest(data / "manifest.json")
    assert m.renderer is not None
    for change, severity in (({"gl_renderer": "llvmpipe (another build)"}, "fail"),
                             ({"numeric_class": "numpy baseline; OpenBLAS Prescott"}, "warn")):  # fmt: skip
        dump_manifest(m.model_copy(update={"renderer": m.renderer.model_copy(update=change)}), data / "manifest.json")
        result = check(validate(data, "reproducibility", regenerate=3), "reproducibility")
        hits = [f for f in result.report.findings if f.reason == Reason.REGENERATION_MISMATCH]
        assert [(f.video_id, f.severity) for f in hits] == [("v000001", severity)], result.summary
        assert "rgb (frame 00002)" in hits[0].message and result.numbers["exact"] is False
        assert result.status == (Status.FAIL if severity == "fail" else Status.WARN)
    assert "the motion is not promised (numeric_class: the physics can go another way)" in hits[0].message
    assert result.numbers["motion_differs"] == ["numeric_class"]
