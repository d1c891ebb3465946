"""`phav-validate` on a whole dataset: a clean `phav generate` output passes every check with
JSON and HTML reports; user errors exit 2; one shard can be checked alone."""

from __future__ import annotations

import json
import shutil

from phav_validators.options import CHECKS
from tests.helpers import invoke_cli, run_cli


def test_clean_dataset_passes_with_reports(small_dataset, tmp_path):
    report, html = tmp_path / "report.json", tmp_path / "report.html"
    result = run_cli("validate!", str(small_dataset), "--workers", "2", "--json", str(report), "--html", str(html))
    assert result.returncode == 0, result.stdout + result.stderr
    data = json.loads(report.read_text(encoding="utf-8"))
    assert data["report_version"] == 1 and data["exit_code"] == 0 and data["status"] in ("pass", "warn")
    (ds,) = data["datasets"]
    assert [c["name"] for c in ds["checks"]] == list(CHECKS)
    statuses = {c["name"]: c["status"] for c in ds["checks"]}
    assert statuses["integrity"] == statuses["encoding"] == statuses["consistency"] == "pass", statuses
    assert statuses["reproducibility"] == "pass" and statuses["distribution"] == "pass", statuses
    repro = next(c for c in ds["checks"] if c["name"] == "reproducibility")
    assert repro["numbers"]["exact"] is True and repro["numbers"]["matched"] == 2
    consistency = next(c for c in ds["checks"] if c["name"] == "consistency")
    assert consistency["numbers"]["worst_flow_mean_epe_px"] < 0.1
    page = html.read_text(encoding="utf-8")
    assert "<svg" in page and "weather" in page and "integrity" in page
    framing = ds["protagonist_framing"]["all"]
    assert framing["frames"] == ds["frames"] and framing["in_view_frames"] > 0
    assert "Protagonist framing" in page and "protagonist framing" in result.stdout


def test_exit_codes_and_single_shard_input(small_dataset, tmp_path):
    missing = invoke_cli("validate!", str(tmp_path / "nope"))
    assert missing.returncode == 2 and "no such file" in missing.stderr and "Traceback" not in missing.stderr
    bad = invoke_cli("validate!", str(small_dataset), "--checks", "integrity,bogus")
    assert bad.returncode == 2 and "--checks" in bad.stderr and "bogus" in bad.stderr
    sample = invoke_cli("validate!", str(small_dataset), "--sample", "0")
    assert sample.returncode == 2 and "--sample" in sample.stderr
    same = tmp_path / "report"  # the HTML was written over the JSON
    both = invoke_cli("validate!", str(small_dataset), "--checks", "schema", "--json", str(same), "--html", str(same))
    assert both.returncode == 2 and "--html: is the --json report's file too" in both.stderr and not same.exists()
    one = invoke_cli("validate!", str(small_dataset / "phav-000001.tar"), "--checks", "integrity,encoding,failures",
                     "--json", str(tmp_path / "one.json"))  # fmt: skip
    assert one.returncode == 0, one.stdout + one.stderr
    (ds,) = json.loads((tmp_path / "one.json").read_text(encoding="utf-8"))["datasets"]
    integrity = ds["checks"][0]
    assert integrity["numbers"]["shards"] == 1 and integrity["numbers"]["videos"] == 1
    assert ds["checks"][2]["numbers"]["videos"] == 1


def test_a_dataset_that_lost_its_manifest_and_shards_is_not_a_recipes_table(small_dataset_copy, tmp_path):
    """A run's directory emptied (or a killed run's) keeps the tables a run writes: it fails
    integrity for what is missing, where it passed as "a recipes table alone"."""
    data = small_dataset_copy
    (data / "manifest.json").unlink()
    for shard in data.glob("*.tar"):
        shard.unlink()
    report = tmp_path / "r.json"
    result = invoke_cli("validate!", str(data), "--checks", "integrity,schema", "--json", str(report))
    checks = {c["name"]: c for c in json.loads(report.read_text())["datasets"][0]["checks"]}
    assert result.returncode == 1 and checks["integrity"]["status"] == "fail"
    assert "MISSING_FILE" in checks["integrity"]["finding_counts"]
    table_alone = tmp_path / "alone"
    table_alone.mkdir()
    (table_alone / "recipes.parquet").write_bytes((data / "recipes.parquet").read_bytes())
    assert invoke_cli("validate!", str(table_alone), "--checks", "schema").returncode == 0


def test_a_run_where_every_check_was_skipped_is_not_a_pass(small_dataset, tmp_path):
    """Integrity asked of a recipes table alone, or reproducibility with no video to make
    again, checks nothing: it said "all checks passed" with exit code 0. Nothing checked is
    no evidence: status ``skip``, exit code 1, and the line says so."""
    table = tmp_path / "alone" / "recipes.parquet"  # beside no dataset
    table.parent.mkdir()
    shutil.copyfile(small_dataset / "recipes.parquet", table)
    cases = [(str(table), "--checks", "integrity,encoding"),
             (str(small_dataset), "--checks", "reproducibility", "--regenerate", "0")]  # fmt: skip
    for i, args in enumerate(cases):
        report = tmp_path / f"r{i}.json"
        result = invoke_cli("validate!", *args, "--json", str(report))
        data = json.loads(report.read_text(encoding="utf-8"))
        assert result.returncode == 1 and data["status"] == "skip" and data["exit_code"] == 1, result.stdout
        assert {c["status"] for c in data["datasets"][0]["checks"]} == {"skip"}
        assert "nothing checked: every check was skipped" in result.stdout and "all checks passed" not in result.stdout
    mixed = invoke_cli("validate!", str(table), "--checks", "integrity,schema")
    assert mixed.returncode == 0 and "all checks passed" in mixed.stdout  # one check ran and passed
