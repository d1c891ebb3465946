"""What a manifest's fingerprint records: phav's version even when it runs from a source checkout,
the CPU's model and SIMD class."""

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


def test_the_fingerprint_records_the_first_processors_model_and_simd_class(monkeypatch):
    monkeypatch.setattr(fingerprint.platform, "machine", lambda: "x86_64")
    monkeypatch.setattr(fingerprint, "cpu_fields", lambda: {"model name": "AMD EPYC", "flags": "sse2 avx avx512_bf16"})
    assert fingerprint._cpu() == ("AMD EPYC", "x86-64-avx")
    monkeypatch.setattr(fingerprint.platform, "machine", lambda: "aarch64")
    monkeypatch.setattr(fingerprint, "cpu_fields", lambda: {"Features": "neon fp"})  # ARM names its flags so
    model = fingerprint.platform.processor() or "aarch64"
    assert fingerprint._cpu() == (model, f"aarch64: {model}")  # not measured: its model decides
