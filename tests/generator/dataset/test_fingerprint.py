"""The versions a manifest records: phav's own even when it runs from a source checkout."""

from __future__ import annotations

import tomllib
from importlib.metadata import PackageNotFoundError
from pathlib import Path

from phav_generator.dataset import fingerprint
from phav_generator.dataset.fingerprint import package_version

ROOT = Path(__file__).resolve().parents[3]


def _not_installed(name: str) -> str:
    raise PackageNotFoundError(name)


def test_phav_run_from_a_checkout_reports_its_pyproject_version(monkeypatch):
    monkeypatch.setattr(fingerprint, "version", _not_installed)
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["version"]
    assert package_version("phav") == declared != "unknown"
    assert package_version("numpy") == "unknown"  # only phav has a source tree to read


def test_a_missing_pyproject_leaves_phav_unknown(monkeypatch, tmp_path):
    monkeypatch.setattr(fingerprint, "version", _not_installed)
    monkeypatch.setattr(fingerprint, "_PYPROJECT", tmp_path / "pyproject.toml")
    assert package_version("phav") == "unknown"


def test_the_fingerprint_records_the_first_processors_model_and_sorted_flags(monkeypatch):
    fields = {"model name": "AMD EPYC", "flags": "sse2 avx512_bf16 fpu"}
    monkeypatch.setattr(fingerprint, "cpu_fields", lambda: fields)
    assert fingerprint._cpu() == ("AMD EPYC", "avx512_bf16 fpu sse2")
    monkeypatch.setattr(fingerprint, "cpu_fields", lambda: {"Features": "neon fp"})  # ARM names its flags so
    assert fingerprint._cpu() == (fingerprint.platform.processor() or fingerprint.platform.machine(), "fp neon")
