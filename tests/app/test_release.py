"""`phav release`: full and recipe-only releases, their card and Croissant description, and
rebuilding a recipe-only release with `phav regenerate` and `phav-validate` (issue: releases)."""

from __future__ import annotations

import json
import re
import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from phav_app.card import check_croissant
from phav_app.release import make_release
from phav_generator.dataset import fingerprint
from phav_spec.encoding import modality, video_content_hash
from phav_spec.errors import PhavUserError
from phav_spec.files import file_sha256
from phav_spec.manifest import dump_manifest, load_manifest
from phav_spec.release import RELEASE_FILE, load_release_index
from phav_spec.webdataset import decode_png
from tests.helpers import file_bytes, invoke_cli, run_cli, theta_variant, tiny, tree_bytes, written_frames
from tests.validators.checks.support import png_edit, refresh_manifest, rewrite_tar, shard_of

CARD_FILES = ("README.md", "croissant.json", RELEASE_FILE)


def croissant_issues(path: Path) -> tuple[list[str], list[str]]:
    """(errors, warnings) of mlcroissant's offline validation, as `mlcroissant validate` runs it."""
    issues = check_croissant(path)
    if issues is None:
        pytest.skip("mlcroissant is not installed (pip install 'phav[croissant]')")
    return issues


@pytest.fixture(scope="module")
def dataset(small_dataset) -> Path:
    """The run's shared small dataset: three phav-v1-tiny videos in two shards."""
    return small_dataset


@pytest.fixture(scope="module")
def recipe_release(dataset, tmp_path_factory) -> Path:
    rel = tmp_path_factory.mktemp("rel") / "recipes-only"
    result = invoke_cli("release", str(dataset), "--out", str(rel), "--recipes-only", "--date", "2026-11-21")
    assert result.returncode == 0, result.stderr
    assert "croissant.json: mlcroissant finds 0 error(s), 0 warning(s)" in result.stdout
    return rel


def test_a_full_release_carries_every_file_with_its_hash(dataset, tmp_path):
    rel = tmp_path / "full"
    result = make_release(dataset, rel, date="2026-11-21")
    index = load_release_index(rel / RELEASE_FILE)
    assert not index.recipes_only and all(f.included for f in index.files)
    manifest = load_manifest(dataset / "manifest.json")
    assert [f.path for f in index.files if f.kind == "shard"] == [s.name for s in manifest.shards]
    for f in index.files:
        assert (rel / f.path).read_bytes() == (dataset / f.path).read_bytes()
        assert file_sha256(rel / f.path) == f.sha256 and (rel / f.path).stat().st_size == f.bytes
    assert result.release_bytes > index.full_bytes  # plus the card, Croissant and histograms
    card = (rel / "README.md").read_text(encoding="utf-8")
    assert "phav-v1-tiny" in card and "## θ" in card and "Holm" in card
    assert "Version 1.0.0, published 2026-11-21; license CC-BY-4.0." in card
    for figure in ("action", "environment", "duration_s"):
        assert f"histograms/{figure}.svg" in card
        assert (rel / "histograms" / f"{figure}.svg").read_text(encoding="utf-8").startswith("<svg")
    errors, warnings = croissant_issues(rel / "croissant.json")
    assert errors == [] and warnings == []


def test_a_full_release_s_files_are_checked_against_release_json(dataset, tmp_path):
    rel = tmp_path / "full"
    make_release(dataset, rel, date="2026-11-21")
    assert _validate(rel, "--checks", "integrity")["_rc"] == 0
    index = json.loads((rel / RELEASE_FILE).read_text(encoding="utf-8"))
    for f in index["files"]:
        if f["path"] == "people.parquet":
            f["sha256"] = "0" * 64
    (rel / RELEASE_FILE).write_text(json.dumps(index), encoding="utf-8")
    (rel / "cameras.parquet").unlink()
    checks = _validate(rel, "--checks", "integrity")
    assert checks["_rc"] == 1
    found = {(f["reason"], f["file"]) for f in checks["integrity"]["findings"]}
    assert found == {("RELEASE_FILE_CHANGED", "people.parquet"), ("MISSING_FILE", "cameras.parquet")}


def test_a_recipe_only_release_s_files_are_checked_against_release_json(recipe_release, tmp_path):
    """The pixels are regenerated into another directory and validated there; the release's
    own files are checked against release.json all the same (an edited θ file passed)."""

    rel = tmp_path / "rel"
    shutil.copytree(recipe_release, rel)
    with (rel / "theta.yaml").open("a", encoding="utf-8") as fh:
        fh.write("# edited\n")
    checks = _validate(rel, "--checks", "integrity", "--regenerate-into", str(tmp_path / "px"))
    assert checks["_rc"] == 1
    assert {(f["reason"], f["file"]) for f in checks["integrity"]["findings"]} == {
        ("RELEASE_FILE_CHANGED", "theta.yaml")
    }


def test_the_license_is_given_and_a_url_is_linked_on_the_card(dataset, tmp_path):
    result = invoke_cli("release", str(dataset), "--out", str(tmp_path / "r0"), "--recipes-only", "--license", " ")
    assert result.returncode == 2 and "--license: give the data's license" in result.stderr
    for option, value in (("--license", "MIT License; see file"), ("--url", "my site")):  # the card's YAML header
        result = invoke_cli("release", str(dataset), "--out", str(tmp_path / "r0"), "--recipes-only", option, value)
        assert result.returncode == 2 and f"{option}: " in result.stderr and repr(value) in result.stderr
    assert not (tmp_path / "r0").exists()
    assert not (tmp_path / "r0").exists()
    url = "https://creativecommons.org/licenses/by-sa/4.0/"
    make_release(dataset, tmp_path / "r1", recipes_only=True, license=url)
    card = (tmp_path / "r1" / "README.md").read_text(encoding="utf-8")
    assert f"license: other\nlicense_link: {url}\n" in card
    make_release(dataset, tmp_path / "r2", recipes_only=True, license="CC-BY-SA-4.0")
    assert "license: cc-by-sa-4.0\n" in (tmp_path / "r2" / "README.md").read_text(encoding="utf-8")


def test_a_full_release_can_be_read_through_croissant(dataset, tmp_path):
    """A Croissant loader reads the recipes and every modality's frames out of the tars, each
    equal to the writer's (flow as its PNG's bytes)."""
    import itertools

    mlc = pytest.importorskip("mlcroissant")
    rel = tmp_path / "full"
    make_release(dataset, rel, date="2026-11-21")
    ds = mlc.Dataset(str(rel / "croissant.json"))
    recipes = list(ds.records("recipes"))
    manifest = load_manifest(dataset / "manifest.json")
    assert sorted(r["recipes/video_id"].decode() for r in recipes) == [v.video_id for v in manifest.videos]
    people = list(ds.records("people"))  # every scalar column of the table
    table = pq.read_table(rel / "people.parquet")
    assert len(people) == table.num_rows
    for column in ("penetration_m", "joint_limit_excess"):
        got = np.array([np.nan if r[f"people/{column}"] is None else r[f"people/{column}"] for r in people])
        want = table.column(column).to_numpy()  # NaN for a background walker (read back as None)
        assert np.allclose(np.sort(got), np.sort(want), equal_nan=True), column
    first = next(iter(ds.records("depth")))
    assert first["depth/key"] == b"v000000/00000" and first["depth/image"].size == (340, 256)
    rgb = list(itertools.islice(ds.records("rgb"), 3))
    assert [r["rgb/key"] for r in rgb] == [b"v000000/00000", b"v000000/00001", b"v000000/00002"]
    written = written_frames(dataset)
    flows = list(mlc.Dataset(str(rel / "croissant.json")).records("flow"))  # a new Dataset: one pass each
    assert len(flows) == len(written)
    for r in flows:  # the PNG's bytes, as the description says: exact 16-bit flow
        got = decode_png(r["flow/image"], modality("flow"))
        assert np.array_equal(got, written[r["flow/key"].decode()]["flow.png"])
    for name, key in (("depth", "depth.png"), ("rgb", "rgb.png"), ("raw_rgb", "raw.png"), ("semantic", "seg.png"),
                      ("instance", "inst.png")):  # fmt: skip
        again = mlc.Dataset(str(rel / "croissant.json"))  # a record set of a tar reads once per Dataset
        frames = {r[f"{name}/key"].decode(): np.asarray(r[f"{name}/image"]) for r in again.records(name)}
        assert sorted(frames) == sorted(written) and all(np.array_equal(frames[k], written[k][key]) for k in written)


def test_the_readme_loading_snippets_run_and_read_exact_flow(dataset, tmp_path, monkeypatch):
    """Each client's snippet in the README's "Loading" section, run as written against a
    release named ``rel``: its flow is one of the writer's frames, bit for bit (the PyTorch
    one's, decoded to pixels, its last batch's)."""
    readme = (Path(__file__).parents[2] / "README.md").read_text(encoding="utf-8")
    section = readme.split("### Loading", 1)[1].split("\n### ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    assert len(blocks) == 4
    make_release(dataset, tmp_path / "rel", date="2026-11-21")
    monkeypatch.chdir(tmp_path)
    written = written_frames(dataset)
    for code in blocks:
        namespace: dict = {}
        exec(compile(code, "README.md", "exec"), namespace)
        flow = namespace["flow"]
        if "PhavClips" in code:  # a batch of clips: TSN frames at the asked size, (u, v) pixels
            assert tuple(flow.shape[1:]) == (3, 128, 170, 2) and len(namespace["label"]) == flow.shape[0]
            continue
        assert flow.dtype == np.uint16 and any(np.array_equal(flow, w["flow.png"]) for w in written.values())


def test_a_full_release_loads_exactly_through_hugging_face_datasets(dataset, tmp_path):
    """load_dataset(RELEASE_DIR) reads the card's frames config: flow as its PNG's bytes, the
    other modalities as exact images, the metadata as the shards' JSON; the tables load
    from their Parquet files, equal to them."""
    datasets = pytest.importorskip("datasets")
    rel = tmp_path / "full"
    make_release(dataset, rel, date="2026-11-21")
    frames = datasets.load_dataset(str(rel), split="train")
    written = written_frames(dataset)
    assert sorted(frames["__key__"]) == sorted(written) and len(frames) == len(written)
    for row in frames:
        want = written[row["__key__"]]
        flow = decode_png(row["flow.png"], modality("flow"))
        assert flow.dtype == np.uint16 and np.array_equal(flow, want["flow.png"])
        for key in ("rgb.png", "raw.png", "seg.png", "inst.png", "depth.png"):
            assert np.array_equal(np.asarray(row[key]), want[key]), key
        assert row["json"]["camera"] == want["json"]["camera"]
        people = {p["person_id"]: p for p in row["json"]["people"]}
        for p in want["json"]["people"]:
            got = people[p["person_id"]]
            assert all(got[k] == p[k] or _both_nan(got[k], p[k]) for k in p), p["person_id"]
    people = datasets.load_dataset("parquet", data_files=str(rel / "people.parquet"), split="train")
    assert people.to_pandas().equals(pq.read_table(rel / "people.parquet").to_pandas())


def test_a_generated_directory_loads_through_datasets_with_flow_cast_to_bytes(dataset):
    """docs/loading.md's line for a directory without a card: every frame's flow exact."""
    datasets = pytest.importorskip("datasets")
    files = sorted(str(p) for p in dataset.glob("*.tar"))
    frames = datasets.load_dataset("webdataset", data_files=files, split="train")
    frames = frames.cast_column("flow.png", datasets.Image(decode=False))
    written = written_frames(dataset)
    assert len(frames) == len(written)
    for row in frames:
        got = decode_png(row["flow.png"]["bytes"], modality("flow"))
        assert np.array_equal(got, written[row["__key__"]]["flow.png"])


def _both_nan(a, b) -> bool:
    return np.array_equal(np.asarray(a, dtype=float), np.asarray(b, dtype=float), equal_nan=True)


def test_a_recipe_only_release_is_small_validates_and_says_how_to_rebuild(dataset, recipe_release):
    index = load_release_index(recipe_release / RELEASE_FILE)
    assert index.recipes_only
    carried = {f.path for f in index.files if f.included}
    assert carried == {"manifest.json", "recipes.parquet", "theta.yaml"}
    assert not list(recipe_release.glob("*.tar")) and not (recipe_release / "people.parquet").exists()
    assert index.full_bytes == sum(p.stat().st_size for p in dataset.iterdir() if p.is_file())
    card = (recipe_release / "README.md").read_text(encoding="utf-8")
    assert "phav regenerate manifest.json --out DIR" in card and "no (regenerate)" in card
    errors, warnings = croissant_issues(recipe_release / "croissant.json")
    assert errors == [] and warnings == []


def test_a_release_is_deterministic_and_a_rerun_keeps_what_is_there(dataset, recipe_release, tmp_path):
    again = make_release(dataset, tmp_path / "again", recipes_only=True, date="2026-11-21")
    assert tree_bytes(tmp_path / "again") == tree_bytes(recipe_release)
    rerun = make_release(dataset, tmp_path / "again", recipes_only=True, date="2026-11-21")
    assert rerun.kept == 3 and again.kept == 0
    assert tree_bytes(tmp_path / "again") == tree_bytes(recipe_release)


def test_an_interrupted_release_is_never_mistaken_for_a_finished_one(dataset, recipe_release, tmp_path):
    out = tmp_path / "again"

    class Stop(Exception):
        pass

    def stop_when_placing(description: str, total: int):
        if description == "placing files":
            raise Stop
        return lambda n: None

    with pytest.raises(Stop):
        make_release(dataset, out, recipes_only=True, date="2026-11-21", progress=stop_when_placing)
    assert not (out / RELEASE_FILE).exists() and (out / ".phav-release.json").exists()
    (out / ".cameras.parquet.link.tmp").write_bytes(b"")  # a link a killed run made (not placed again here)
    (out / ".README.md.0123456789abcdef.tmp").write_bytes(b"half a card")  # and a write it began
    (out / "histograms").mkdir(exist_ok=True)
    (out / "histograms" / ".action.svg.fedcba9876543210.tmp").write_bytes(b"<svg")
    make_release(dataset, out, recipes_only=True, date="2026-11-21")  # resumes its own directory
    assert tree_bytes(out) == tree_bytes(recipe_release)  # neither temporary left in it


def test_release_refuses_what_it_cannot_vouch_for(dataset, recipe_release, tmp_path):
    unfinished = tmp_path / "unfinished"
    shutil.copytree(dataset, unfinished)
    (unfinished / "manifest.json").unlink()
    result = invoke_cli("release", str(unfinished), "--out", str(tmp_path / "r1"))
    assert result.returncode == 2 and "no manifest.json" in result.stderr and "Traceback" not in result.stderr

    tampered = tmp_path / "tampered"
    shutil.copytree(dataset, tampered)
    shard = sorted(tampered.glob("*.tar"))[1]
    data = bytearray(shard.read_bytes())
    data[600] ^= 0xFF
    shard.write_bytes(bytes(data))
    with pytest.raises(PhavUserError, match="changed since it was generated") as caught:
        make_release(tampered, tmp_path / "r2")
    assert shard.name in str(caught.value)

    for name, damage in (("people.parquet", b"garbage\n"), ("cameras.parquet", None)):
        broken = tmp_path / f"broken-{name}"
        shutil.copytree(dataset, broken)
        if damage is None:  # a well-formed table of another dataset's videos
            table = pq.read_table(broken / name)
            ids = pa.array(["v999999"] * table.num_rows)
            pq.write_table(table.set_column(0, "video_id", ids), broken / name)
        else:
            (broken / name).write_bytes(damage)
        result = invoke_cli("release", str(broken), "--out", str(tmp_path / f"r-{name}"))
        assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
        assert f"{broken / name}: " in result.stderr and "phav-validate" in result.stderr
        assert not (tmp_path / f"r-{name}").exists()

    # Recipes that are not the videos': another seed's under the same ids, or a blank cell.
    # A recipe-only release of them was written, exit 0, and could never be rebuilt.
    other = tmp_path / "other-seed"
    shutil.copytree(dataset, other)
    manifest = json.loads((dataset / "manifest.json").read_text(encoding="utf-8"))
    n = len(manifest["videos"])
    seed = str(manifest["dataset_seed"] + 1)
    sampled = invoke_cli("sample", "--theta", str(dataset / "theta.yaml"), "--n", str(n), "--seed", seed, "--out",
                         str(tmp_path / "other.parquet"))  # fmt: skip
    assert sampled.returncode == 0, sampled.stderr
    shutil.move(tmp_path / "other.parquet", other / "recipes.parquet")
    result = invoke_cli("release", str(other), "--out", str(tmp_path / "r-seed"), "--recipes-only")
    assert result.returncode == 2 and "phav.dataset_seed: recipes of seed" in result.stderr, result.stderr
    blank = tmp_path / "blank"
    shutil.copytree(dataset, blank)
    rows = pq.read_table(blank / "recipes.parquet")
    cells = rows.column("recipe").to_pylist()
    column = rows.schema.get_field_index("recipe")
    blanked = rows.set_column(column, "recipe", pa.array([*cells[:-1], None], pa.string()))
    pq.write_table(blanked.replace_schema_metadata(rows.schema.metadata), blank / "recipes.parquet")
    result = invoke_cli("release", str(blank), "--out", str(tmp_path / "r-blank"), "--recipes-only")
    assert result.returncode == 2 and "recipe: no recipe" in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "r-seed").exists() and not (tmp_path / "r-blank").exists()

    result = invoke_cli("release", str(dataset), "--out", str(recipe_release))  # full into a recipe-only one
    assert result.returncode == 2 and "holds other files or another release" in result.stderr
    busy = tmp_path / "busy"
    busy.mkdir()
    (busy / "README.md").write_text("someone else's", encoding="utf-8")
    result = invoke_cli("release", str(dataset), "--out", str(busy))
    assert result.returncode == 2 and "holds other files" in result.stderr
    assert (busy / "README.md").read_text(encoding="utf-8") == "someone else's"
    for inside in (dataset.parent, dataset / "rel"):  # a release never holds its dataset, nor the reverse
        result = invoke_cli("release", str(dataset), "--out", str(inside))
        assert result.returncode == 2 and "must not contain each other" in result.stderr
    for date in ("21/11/2026", "20261121", "2026-W47-6"):  # Python's own parser takes the last two
        result = invoke_cli("release", str(dataset), "--out", str(tmp_path / "r3"), "--date", date)
        assert result.returncode == 2 and f"--date: not a date (YYYY-MM-DD): '{date}'" in result.stderr
    result = invoke_cli("release", str(dataset), "--out", str(tmp_path / "r3"), "--dataset-version", "v2")
    assert result.returncode == 2 and "--dataset-version" in result.stderr


def test_regenerate_rebuilds_a_recipe_only_release_and_checks_every_hash(dataset, recipe_release, tmp_path):
    out = tmp_path / "rebuilt"
    result = invoke_cli("regenerate", str(recipe_release / "manifest.json"), "--out", str(out), "--workers", "2")
    assert result.returncode == 0, result.stderr
    assert "3/3 videos match; files: 4/4 sha256 match" in result.stdout  # 2 shards, 2 tables
    assert file_bytes(out) == file_bytes(dataset)

    result = invoke_cli("regenerate", str(recipe_release / "manifest.json"), "--out", str(recipe_release))
    assert result.returncode == 2 and "--out" in result.stderr and "apart from the source" in result.stderr

    # Asked again into the same directory, nothing is rebuilt: its shards are read again,
    # not taken from its manifest, so a byte changed since is a mismatch.
    shard = out / "phav-000000.tar"
    data = bytearray(shard.read_bytes())
    data[len(data) // 2] ^= 0xFF
    shard.write_bytes(bytes(data))
    result = invoke_cli("regenerate", str(recipe_release / "manifest.json"), "--out", str(out))
    assert result.returncode == 1 and "already held these 3 video(s), nothing rebuilt" in result.stdout
    assert "mismatch phav-000000.tar: sha256" in result.stdout

    # A release whose metadata table no longer matches what the recipes render is caught, and
    # one listing a metadata file phav does not make is a mismatch, not a crash.
    bad = tmp_path / "bad"
    shutil.copytree(recipe_release, bad)
    index = json.loads((bad / RELEASE_FILE).read_text(encoding="utf-8"))
    people = next(f for f in index["files"] if f["path"] == "people.parquet")
    people["sha256"] = "0" * 64
    index["files"].append({**people, "path": "objects.parquet"})
    (bad / RELEASE_FILE).write_text(json.dumps(index), encoding="utf-8")
    result = invoke_cli("regenerate", str(bad / "manifest.json"), "--out", str(tmp_path / "rebuilt2"))
    assert result.returncode == 1 and "Traceback" not in result.stderr, result.stderr
    assert "mismatch people.parquet: sha256" in result.stdout and "files: 3/5 sha256 match" in result.stdout
    assert "mismatch objects.parquet: listed as metadata by release.json, not made by phav" in result.stdout


def _as_another_renderer_made_it(folder: Path, edit_frame: Callable[[np.ndarray], np.ndarray] | None) -> None:
    """The manifest of ``folder`` as if another renderer made it: its fingerprint another
    llvmpipe's, and (``edit_frame``) v000000's frame 1 drawn otherwise, its hashes with it."""
    if edit_frame is not None:
        rewrite_tar(shard_of(folder, "v000000"), png_edit("v000000/00001.rgb.png", edit_frame))
        refresh_manifest(folder)
    manifest = load_manifest(folder / "manifest.json")
    assert manifest.renderer is not None
    renderer = manifest.renderer.model_copy(update={"gl_renderer": manifest.renderer.gl_renderer + " (another build)"})
    dump_manifest(manifest.model_copy(update={"renderer": renderer}), folder / "manifest.json")


def test_regenerate_by_another_renderer_compares_pixels_within_tolerances(small_dataset_copy, recipe_release, tmp_path):
    """Another renderer's pixels are not promised bit for bit: a video whose hash differs is
    compared with the source's frames within phav-validate's tolerances (exit 0 within them,
    1 beyond), and where the source has no frames the report says it could not verify."""
    _as_another_renderer_made_it(small_dataset_copy, lambda rgb: np.clip(rgb.astype(int) + 2, 0, 255).astype(np.uint8))
    result = invoke_cli("regenerate", str(small_dataset_copy), "--out", str(tmp_path / "near"))
    assert result.returncode == 0, result.stdout + result.stderr
    assert "2/3 videos match" in result.stdout and "equal pixels not promised" in result.stdout
    assert "1 video(s) whose hashes differ compared frame by frame" in result.stdout and "mismatch" not in result.stdout

    _as_another_renderer_made_it(small_dataset_copy, lambda rgb: 255 - rgb)
    result = invoke_cli("regenerate", str(small_dataset_copy), "--out", str(tmp_path / "far"))
    assert result.returncode == 1, result.stdout + result.stderr
    assert "mismatch v000000: rgb beyond tolerance from frame 00001" in result.stdout

    release = tmp_path / "release"
    shutil.copytree(recipe_release, release)
    _as_another_renderer_made_it(release, None)
    manifest = load_manifest(release / "manifest.json")
    other = {**manifest.videos[1].modality_hashes, "rgb": "0" * 64}  # v000001's rgb drawn otherwise
    videos = [*manifest.videos]
    videos[1] = videos[1].model_copy(update={"modality_hashes": other, "content_hash": video_content_hash(other)})
    dump_manifest(manifest.model_copy(update={"videos": videos}), release / "manifest.json")
    result = invoke_cli("regenerate", str(release / "manifest.json"), "--out", str(tmp_path / "unseen"))
    assert result.returncode == 0, result.stdout + result.stderr
    assert "not verified: 1 video(s) whose hashes differ have no frames in the source" in result.stdout


def _validate(release: Path, *extra: str) -> dict:
    out = release.parent / f"{release.name}-report.json"
    result = invoke_cli("validate!", str(release), "--json", str(out), *extra)
    assert result.returncode in (0, 1), result.stderr
    report = json.loads(out.read_text(encoding="utf-8"))["datasets"][0]
    return {c["name"]: c for c in report["checks"]} | {"_rc": result.returncode, "_stdout": result.stdout}


@pytest.fixture(scope="module")
def local_validation(recipe_release, tmp_path_factory) -> tuple[dict, Path]:
    """phav-validate of the recipe-only release with the local pool, and where it regenerated."""
    px = tmp_path_factory.mktemp("validate") / "px"
    return _validate(recipe_release, "--workers", "2", "--regenerate-into", str(px)), px


def test_phav_validate_regenerates_a_recipe_only_release(recipe_release, local_validation):
    checks, px = local_validation
    assert checks["_rc"] == 0, checks["_stdout"]
    assert all(checks[c]["status"] == "pass" for c in ("integrity", "encoding", "consistency", "reproducibility"))
    assert checks["integrity"]["numbers"]["hashed"] == 3
    assert any("regenerated 2 of 2 shards" in n for n in checks["integrity"]["notes"])
    assert sorted(p.name for p in px.glob("*.tar")) == ["phav-000000.tar", "phav-000001.tar"]
    # Asked again with the same directory, the shards are reused (and their hashes verified again).
    again = _validate(recipe_release, "--checks", "integrity", "--regenerate-into", str(px))
    assert any("reused 2 of 2 shards" in n for n in again["integrity"]["notes"])
    assert again["integrity"]["status"] == "pass"


def test_a_regeneration_is_reused_only_whole_and_resumed_where_it_stopped(recipe_release, local_validation, tmp_path):
    """A shard gone from an earlier regeneration: made again, not blamed on the release. A
    run stopped while the release's own files were copied in (its marker still "begun"):
    the same request finishes it."""
    _, px = local_validation
    damaged = tmp_path / "damaged"
    shutil.copytree(px, damaged)
    (damaged / "phav-000000.tar").unlink()
    checks = _validate(recipe_release, "--checks", "integrity", "--regenerate-into", str(damaged))
    assert checks["_rc"] == 0 and any("regenerated 2 of 2 shards" in n for n in checks["integrity"]["notes"])
    stopped = tmp_path / "stopped"
    shutil.copytree(px, stopped)
    marker = stopped / ".phav-regenerated.json"
    marker.write_text(json.dumps(json.loads(marker.read_text(encoding="utf-8")) | {"begun": True}), encoding="utf-8")
    shards = {p.name: p.stat().st_mtime_ns for p in stopped.glob("*.tar")}
    checks = _validate(recipe_release, "--checks", "integrity", "--regenerate-into", str(stopped))
    assert checks["_rc"] == 0 and checks["integrity"]["status"] == "pass", checks["_stdout"]
    assert {p.name: p.stat().st_mtime_ns for p in stopped.glob("*.tar")} == shards  # not rendered again
    assert "begun" not in json.loads(marker.read_text(encoding="utf-8"))


def test_a_recipe_only_release_regenerated_with_other_numerics_is_another_renderer(recipe_release, tmp_path):
    """OpenBLAS on another CPU's kernels stands in for a machine of the same SIMD class with
    other numerics, which can move the physics: the note names them, and what differs is a
    warning (equal pixels are not promised there), not a failure."""
    other = "Sandybridge" if fingerprint._openblas_core() == "Haswell" else "Haswell"
    out = tmp_path / "report.json"
    result = run_cli("validate!", str(recipe_release), "--json", str(out), "--checks", "integrity",
                     env={"OPENBLAS_CORETYPE": other})  # fmt: skip
    assert result.returncode == 0, result.stdout
    integrity = json.loads(out.read_text(encoding="utf-8"))["datasets"][0]["checks"][0]
    assert integrity["numbers"]["hashed"] == 3 and integrity["status"] in ("pass", "warn")
    assert any("differs from the release's (numeric_class)" in n for n in integrity["notes"]), integrity["notes"]
    assert all(f["severity"] == "warn" for f in integrity["findings"])


def test_an_interrupted_regeneration_into_a_directory_is_resumed(recipe_release, tmp_path):
    """Ctrl-C half-way through --regenerate-into: the directory is the run's (its marker says
    so before the first write), and the same request resumes it."""
    px = tmp_path / "px"
    stopped = run_cli("validate!", str(recipe_release), "--checks", "integrity", "--regenerate-into", str(px),
                      env={"PHAV_FAULT_KILL_AT": "part-done:v000001", "PHAV_FAULT_SIGNAL": "INT"})  # fmt: skip
    assert stopped.returncode == 130, stopped.stderr
    assert json.loads((px / ".phav-regenerated.json").read_text(encoding="utf-8"))["begun"] is True
    again = _validate(recipe_release, "--checks", "integrity", "--regenerate-into", str(px))
    assert again["_rc"] == 0 and again["integrity"]["status"] == "pass", again["_stdout"]
    assert any("regenerated 2 of 2 shards" in n for n in again["integrity"]["notes"])
    assert "begun" not in json.loads((px / ".phav-regenerated.json").read_text(encoding="utf-8"))


def test_recipe_checks_of_a_recipe_only_release_need_no_pixels(recipe_release, tmp_path):
    checks = _validate(recipe_release, "--checks", "schema,distribution", "--regenerate-into", str(tmp_path / "px"))
    assert checks["_rc"] == 0 and checks["schema"]["status"] == "pass", checks["_stdout"]
    assert not (tmp_path / "px").exists()


def test_phav_validate_regenerates_only_the_sampled_shards_then_others_when_asked(recipe_release, tmp_path):
    """--sample regenerates only the shards holding the sampled videos; a later full run in
    the same directory clears them and regenerates every shard, so the metadata tables cover
    every video (the failures check reads them)."""
    px = str(tmp_path / "px")
    first = _validate(recipe_release, "--checks", "integrity,encoding", "--sample", "0.25", "--regenerate-into", px)
    assert first["_rc"] == 0, first["_stdout"]
    assert any("regenerated 1 of 2 shards" in n and "every video in them checked" in n
               for n in first["integrity"]["notes"])  # fmt: skip
    assert len(list((tmp_path / "px").glob("*.tar"))) == 1
    [made] = (tmp_path / "px").glob("*.tar")
    in_shard = next(len(s.video_ids) for s in load_manifest(tmp_path / "px" / "manifest.json").shards
                    if s.name == made.name)  # fmt: skip
    assert first["integrity"]["numbers"]["hashed"] == in_shard  # the shard's videos, not a sample of them
    full = _validate(recipe_release, "--checks", "integrity,failures", "--regenerate-into", px)
    assert full["_rc"] == 0, full["_stdout"]
    assert any("regenerated 2 of 2 shards" in n for n in full["integrity"]["notes"])
    assert full["failures"]["status"] == "pass"


def test_phav_validate_says_what_is_wrong_with_a_broken_release(recipe_release, tmp_path):
    broken = tmp_path / "broken"
    shutil.copytree(recipe_release, broken)
    (broken / "recipes.parquet").unlink()
    checks = _validate(broken)
    assert checks["_rc"] == 1 and "Traceback" not in checks["_stdout"]
    assert any("cannot regenerate the release" in n for n in checks["integrity"]["notes"])
    assert checks["schema"]["finding_counts"] == {"MISSING_FILE": 1}

    result = invoke_cli("validate!", str(recipe_release), "--regenerate-into", str(recipe_release / "px"))
    assert result.returncode == 2 and "--regenerate-into" in result.stderr and "Traceback" not in result.stderr
    assert not (recipe_release / "px").exists()

    no_theta = tmp_path / "no-theta"
    shutil.copytree(recipe_release, no_theta)
    (no_theta / "theta.yaml").unlink()
    checks = _validate(no_theta)
    assert checks["_rc"] == 1 and any("theta.yaml missing" in n for n in checks["integrity"]["notes"])
    assert any(f["reason"] == "MISSING_FILE" and f["file"] == "theta.yaml" for f in checks["integrity"]["findings"])
    # The checks asked for: those that need no pixels run, the rest are skipped with why.
    asked = _validate(no_theta, "--checks", "integrity,encoding")
    assert "schema" not in asked and asked["encoding"]["status"] == "skip"
    assert "cannot regenerate the release: " in asked["encoding"]["summary"]

    corrupt = tmp_path / "corrupt"
    shutil.copytree(recipe_release, corrupt)
    (corrupt / RELEASE_FILE).write_text("{not json", encoding="utf-8")
    checks = _validate(corrupt, "--checks", "integrity,schema")
    assert checks["_rc"] == 1 and checks["integrity"]["finding_counts"]["MANIFEST_INVALID"] == 1


def test_phav_validate_fails_a_recipe_only_release_whose_hashes_lie(recipe_release, tmp_path):
    """The release promises a content hash its recipe does not render: integrity fails."""
    bad = tmp_path / "bad"
    shutil.copytree(recipe_release, bad)
    manifest = load_manifest(bad / "manifest.json")
    video = manifest.videos[1]
    hashes = dict(video.modality_hashes) | {"depth": "0" * 64}
    lied = video.model_copy(update={"modality_hashes": hashes, "content_hash": video_content_hash(hashes)})
    videos = [lied if v.video_id == video.video_id else v for v in manifest.videos]
    dump_manifest(manifest.model_copy(update={"videos": videos}), bad / "manifest.json")
    page = tmp_path / "report.html"
    checks = _validate(bad, "--checks", "integrity", "--html", str(page))
    assert checks["_rc"] == 1
    assert checks["integrity"]["status"] == "fail"
    # The edited manifest is no longer the one release.json records, either.
    assert checks["integrity"]["finding_counts"] == {"HASH_MISMATCH": 1, "RELEASE_FILE_CHANGED": 1}
    # The flagged video's frame is on the page, read before the temporary shards went.
    html = page.read_text(encoding="utf-8")
    assert "<h3>Flagged videos</h3>" in html and f"{video.video_id} frame 00000" in html


@pytest.mark.slow
def test_phav_validate_on_ray_reports_what_the_local_pool_reports(ray_with_delays, recipe_release, local_validation,
                                                                  tmp_path):  # fmt: skip
    local, px = local_validation
    ray = _validate(recipe_release, "--workers", "2", "--engine", "ray", "--regenerate-into", str(tmp_path / "ray"))
    assert local["_rc"] == 0, local["_stdout"]
    assert any("regenerated 2 of 2 shards" in n for n in ray["integrity"]["notes"])  # rendered on Ray too
    assert file_bytes(tmp_path / "ray") == file_bytes(px)
    for name in ("integrity", "schema", "encoding", "distribution", "failures", "consistency", "reproducibility"):
        assert (ray[name]["status"], ray[name]["numbers"]) == (local[name]["status"], local[name]["numbers"]), name


@pytest.mark.slow
def test_a_recipe_only_release_of_100_videos(tmp_path):
    """Issue 7's release check: 100 videos; the recipe-only release is under 1 % of the full
    release's bytes, regenerates with every hash matching, and its Croissant file validates.
    Clips of 0.1 s (3 frames) keep it quick, and make the 1 % harder to meet: recipes cost the
    same, pixels a fraction (0.71 % here; phav-v1's 1–10 s clips give far less). The default
    tests check the rest on the shared 3-video release: everything but the 1 % at 100 videos."""

    def three_frames(data: dict) -> None:
        tiny(data)
        data["durations"] = {"t_min": 0.1, "t_max": 0.1, "t_mod": 0.1}

    theta = theta_variant(tmp_path, three_frames)
    data, rel = tmp_path / "data", tmp_path / "rel"
    result = run_cli("generate", "--theta", str(theta), "--videos", "100", "--seed", "7", "--workers", "2",
                     "--out", str(data))  # fmt: skip
    assert result.returncode == 0, result.stderr
    result = run_cli("release", str(data), "--out", str(rel), "--recipes-only", "--date", "2026-11-21")
    assert result.returncode == 0, result.stderr
    release_bytes = sum(p.stat().st_size for p in rel.rglob("*") if p.is_file())
    full_bytes = load_release_index(rel / RELEASE_FILE).full_bytes
    assert release_bytes < 0.01 * full_bytes, (release_bytes, full_bytes)
    errors, warnings = croissant_issues(rel / "croissant.json")
    assert errors == [] and warnings == []
    rebuilt = tmp_path / "rebuilt"
    result = run_cli("regenerate", str(rel / "manifest.json"), "--out", str(rebuilt), "--workers", "2")
    assert result.returncode == 0, result.stdout + result.stderr
    n_shards = len(load_manifest(rel / "manifest.json").shards)
    assert f"100/100 videos match; files: {n_shards + 2}/{n_shards + 2} sha256 match" in result.stdout
    assert file_bytes(rebuilt) == file_bytes(data)


def test_previewing_a_recipe_only_release_says_it_carries_no_shards(recipe_release, tmp_path):
    result = invoke_cli("preview", str(recipe_release), "--out", str(tmp_path / "s.png"))
    assert result.returncode == 2 and "a recipe-only release carries no shards" in result.stderr, result.stderr


def test_a_recipe_only_release_s_findings_name_its_own_files(recipe_release, tmp_path):
    """The release's recipes table with a video twice: the schema finding names the release's
    table, not its copy in the temporary directory the pixels were regenerated into."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    rel = tmp_path / "rel"
    shutil.copytree(recipe_release, rel)
    rows = pq.read_table(rel / "recipes.parquet")
    pq.write_table(pa.concat_tables([rows, rows.slice(0, 1)]), rel / "recipes.parquet")
    checks = _validate(rel, "--checks", "integrity,schema")
    files = {f["file"] for f in checks["schema"]["findings"] if f["reason"] == "DUPLICATE_VIDEO"}
    assert files == {str(rel / "recipes.parquet")}, checks["schema"]["findings"]


@pytest.mark.parametrize("name", [".", "..", "...", "a/b", ""])
def test_a_release_index_names_files_not_folders(recipe_release, tmp_path, name):
    """release.json's paths are files' names beside it: "." or ".." would name a folder (a
    crash where the regenerated files are compared), a slash another folder's file."""
    index = json.loads((recipe_release / RELEASE_FILE).read_text(encoding="utf-8"))
    index["files"][0]["path"] = name
    (tmp_path / RELEASE_FILE).write_text(json.dumps(index), encoding="utf-8")
    with pytest.raises(PhavUserError, match=r"files\.0\.path"):
        load_release_index(tmp_path / RELEASE_FILE)
