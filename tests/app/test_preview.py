"""`phav preview`: a contact sheet of every modality and a GIF of one video."""

from __future__ import annotations

from PIL import Image

from tests.helpers import invoke_cli


def test_preview_sheets_all_modalities_and_a_gif(small_dataset, small_recipes, tmp_path):
    out = tmp_path / "sheet.png"
    result = invoke_cli("preview", str(small_dataset), "--video", "v000001", "--frames", "3", "--out", str(out))
    assert result.returncode == 0, result.stderr
    sheet = Image.open(out)
    assert sheet.size == (6 * 340, 18 + 3 * 256)
    gif = Image.open(out.with_suffix(".gif"))
    assert gif.n_frames == small_recipes[1].n_frames
    result = invoke_cli("preview", str(small_dataset), "--video", "v009999", "--out", str(out))
    assert result.returncode == 2 and "v009999" in result.stderr


def test_the_sheet_is_named_png_and_an_empty_dataset_is_said(small_dataset, tmp_path, small_recipes):
    """`--out clip.gif` wrote PNG bytes into clip.gif and the GIF into clip-rgb.gif: the sheet
    is a PNG, named so. `--video` with a recipe JSON was ignored, and `--skeleton` with a
    dataset blamed its manifest: both are one-line errors naming the option."""
    out = tmp_path / "clip.gif"
    result = invoke_cli("preview", str(small_dataset), "--frames", "2", "--out", str(out))
    assert result.returncode == 2 and "--out: the sheet is a PNG: name it .png" in result.stderr, result.stderr
    assert not out.exists()
    recipe = tmp_path / "r.json"
    recipe.write_text(small_recipes[0].model_dump_json(), encoding="utf-8")
    result = invoke_cli("preview", str(recipe), "--video", "v000003")
    assert result.returncode == 2 and "--video: picks a video of a dataset" in result.stderr
    result = invoke_cli("preview", str(small_dataset), "--skeleton")
    assert result.returncode == 2 and "--skeleton: draws a recipe JSON's people" in result.stderr
    empty = tmp_path / "empty"
    assert invoke_cli("sample", "--n", "0", "--out", str(tmp_path / "none.parquet")).returncode == 0
    assert invoke_cli("regenerate", str(tmp_path / "none.parquet"), "--out", str(empty)).returncode == 0
    result = invoke_cli("preview", str(empty))
    assert result.returncode == 2 and result.stderr.strip().endswith("manifest.json: the dataset holds no videos")


def test_a_frame_of_another_size_is_one_line_naming_it(small_dataset_copy, tmp_path):
    """A shard whose image of one frame has another size than the video's (re-encoded by
    hand): the preview names the member, where it raised a numpy traceback."""
    import io
    import tarfile

    import cv2
    import numpy as np

    shard = small_dataset_copy / "phav-000000.tar"
    with tarfile.open(shard) as tar:
        members = [(m, tar.extractfile(m).read()) for m in tar.getmembers()]
    name = "v000001/00003.seg.png"
    with tarfile.open(shard, "w", format=tarfile.USTAR_FORMAT) as tar:
        for m, data in members:
            if m.name == name:
                data = cv2.imencode(".png", np.zeros((100, 100, 3), np.uint8))[1].tobytes()
                m.size = len(data)
            tar.addfile(m, io.BytesIO(data))
    result = invoke_cli("preview", str(small_dataset_copy), "--video", "v000001", "--out", str(tmp_path / "s.png"))
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert result.returncode == 2 and len(lines) == 1 and f"{name} is 100×100, the video's frames 340×256" in lines[0]
