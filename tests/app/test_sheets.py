"""`phav sheets`: one image per value of a variable over one base scene, and an index."""

from __future__ import annotations

import numpy as np
from PIL import Image

from phav_spec.vocab import ACTIONS, DAY_PHASES, WEATHERS
from tests.helpers import invoke_cli, theta_variant


def test_sheets_make_one_image_per_value_and_an_index(tmp_path):
    """Weather sheets: one JPEG per weather of one base scene, listed by the index page, and
    different from each other only where the weather shows (the labels row is shared)."""
    out = tmp_path / "sheets"
    result = invoke_cli("sheets", "--by", "weather", "--out", str(out))
    assert result.returncode == 0, result.stderr
    images = {w: np.asarray(Image.open(out / f"weather-{w}.jpg")) for w in WEATHERS.names}
    index = (out / "README.md").read_text()
    assert all(f"weather-{w}.jpg" in index for w in WEATHERS.names)
    assert f"Made by `phav sheets --theta phav-v1 --seed 0 --by weather --out {out}`" in index  # runs again as is
    shapes = {im.shape for im in images.values()}
    assert shapes == {(18 + 2 * 256, 3 * 340, 3)}
    rgb = {w: im[18 : 18 + 256].astype(float) for w, im in images.items()}  # the RGB row
    labels = {w: im[18 + 256 + 20 :, :340].astype(float) for w, im in images.items()}  # semantic tile
    assert np.abs(rgb["fog"] - rgb["clear"]).mean() > 5.0
    assert max(np.abs(labels[w] - labels["clear"]).mean() for w in WEATHERS.names) < 1.0
    bad = invoke_cli("sheets", "--by", "mood", "--out", str(out))
    assert bad.returncode == 2 and "mood" in bad.stderr and "Traceback" not in bad.stderr


def test_sheets_never_replace_a_readme_they_did_not_write(tmp_path):
    """The index page is README.md: a folder with a project's README or a dataset (a
    release's card) was overwritten without a word. Refused before any rendering; a folder
    of sheets is written again."""
    project = tmp_path / "project"
    project.mkdir()
    (project / "README.md").write_text("# My notes\n", encoding="utf-8")
    result = invoke_cli("sheets", "--by", "weather", "--out", str(project))
    assert result.returncode == 2 and "README.md that phav sheets did not write" in result.stderr, result.stderr
    assert (project / "README.md").read_text(encoding="utf-8") == "# My notes\n"
    assert list(project.iterdir()) == [project / "README.md"]
    dataset = tmp_path / "dataset"
    dataset.mkdir()
    (dataset / "manifest.json").write_text("{}", encoding="utf-8")
    result = invoke_cli("sheets", "--by", "weather", "--out", str(dataset))
    assert result.returncode == 2 and "holds a dataset" in result.stderr and "Traceback" not in result.stderr


def test_sheets_show_the_actions_and_environments_theta_gives_a_chance(tmp_path):
    """A θ of walks and runs only: `phav sheets` failed ("no recipe with action brush_hair
    among the first 20,000") and made no sheet. Its action sheets are now walk and run; the
    weather and day-phase sheets force every value on one base scene, as before; a kind
    named twice is made once."""
    from phav_app.sheets import sheet_specs
    from phav_spec.theta import load_theta

    def walkers(data):
        data["theta_a"] = {a: (1.0 if a in ("walk", "run") else 0.0) for a in ACTIONS.names}

    theta = load_theta(theta_variant(tmp_path, walkers))
    specs = list(sheet_specs(theta, 0, ("action", "action", "day_phase")))
    walks = [("action", a) for a in ACTIONS.names if a in ("walk", "run")]  # the vocabulary's order
    assert [(s.kind, s.value) for s in specs] == walks + [("day_phase", d) for d in DAY_PHASES.names]
    assert all(s.recipe.action == s.value for s in specs if s.kind == "action")


def test_the_index_names_the_command_that_makes_the_sheets_again(tmp_path):
    """The index printed θ's name (a θ file's is not a preset) and left out --by: its command
    made other sheets. It now gives the θ as given, the kinds where not all, and the folder."""
    from phav_app.sheets import SHEET_KINDS, sheets_command

    theta = tmp_path / "my theta.yaml"
    assert sheets_command(str(theta), 3, tuple(SHEET_KINDS), tmp_path / "out") == (
        f"phav sheets --theta '{theta}' --seed 3 --out {tmp_path / 'out'}")  # fmt: skip
    assert sheets_command("phav-v1", 0, ("action", "weather", "action"), tmp_path).endswith(
        f"--by action,weather --out {tmp_path}")  # fmt: skip
