"""Every script under docs/measure imports what exists today: the docs' figures are reproduced
by those scripts, and a name removed from the packages (or from a sibling script) must not
leave a page's command failing at its first line. Read from the source (nothing is run: some
scripts measure at import)."""

from __future__ import annotations

import ast
import importlib
import importlib.util
from pathlib import Path

import pytest

MEASURE = Path(__file__).resolve().parents[1] / "docs" / "measure"
SCRIPTS = sorted(MEASURE.glob("*.py"))
#: The packages whose names a script may import; anything else is a third-party library.
OURS = ("phav_spec", "phav_generator", "phav_validators", "phav_app")


def _top_level_names(path: Path) -> set[str]:
    """The names a module defines at its top level (functions, classes, assignments, imports)."""
    names: set[str] = set()
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Assign):
            for target in node.targets:  # `W, H = 340, 256` defines both
                names.update(t.id for t in ast.walk(target) if isinstance(t, ast.Name))
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
        elif isinstance(node, ast.Import | ast.ImportFrom):
            names.update((a.asname or a.name).split(".")[0] for a in node.names)
    return names


def _submodule(package: object, name: str) -> bool:
    """Whether ``name`` is a submodule of ``package`` (``from phav_app import cli``)."""
    return hasattr(package, "__path__") and importlib.util.find_spec(f"{package.__name__}.{name}") is not None


def _missing(script: Path) -> list[str]:
    """``module.name`` for every name the script imports from our packages or a sibling script
    that is not there."""
    missing = []
    for node in ast.walk(ast.parse(script.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):  # `import phav_generator.gone`
            missing += [a.name for a in node.names if a.name.split(".")[0] in OURS
                        and importlib.util.find_spec(a.name) is None]  # fmt: skip
            continue
        if not isinstance(node, ast.ImportFrom) or node.module is None or node.level:
            continue
        sibling = MEASURE / f"{node.module}.py"
        if sibling.exists():
            defined = _top_level_names(sibling)
            missing += [f"{node.module}.{a.name}" for a in node.names if a.name not in defined]
        elif node.module.split(".")[0] in OURS:
            module = importlib.import_module(node.module)
            missing += [f"{node.module}.{a.name}" for a in node.names if not hasattr(module, a.name)
                        and not _submodule(module, a.name)]  # fmt: skip
    return missing


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_a_measure_script_imports_only_what_exists(script: Path) -> None:
    assert _missing(script) == []


def test_a_removed_name_is_caught(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The check is not vacuous: an import of a name the package lacks is reported."""
    fake = tmp_path / "fake.py"
    fake.write_text("from phav_app.cli import sample_table\nfrom phav_spec.vocab import ACTIONS\n"
                    "import phav_generator.gone\nimport phav_spec.vocab\n"
                    "from judged_frames import dumped, gone\n", encoding="utf-8")  # fmt: skip
    assert _missing(fake) == ["phav_app.cli.sample_table", "phav_generator.gone", "judged_frames.gone"]
    assert len(SCRIPTS) > 30
