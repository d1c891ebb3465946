"""Reports of ``phav-validate`` as files: JSON (schema in docs/validation.md) and HTML.

The HTML page is self-contained (inline SVG histograms, frames as base64 PNG): per
dataset the check table, observed against expected shares per variable, the protagonist's
framing (size histogram per camera), and the first flagged frame of each of the worst videos.
"""

from __future__ import annotations

import base64
import html
import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from phav_generator.dataset.fingerprint import package_version
from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write
from phav_spec.judge_classes import JUDGE_CLASSES
from phav_spec.manifest import load_manifest
from phav_validators.checks.reproduce import shard_video_frames
from phav_validators.findings import figure_text
from phav_validators.framing import FRAMING_BINS, FramingResult
from phav_validators.learn.learnability import LearnResult, confusion_png
from phav_validators.options import DatasetReport, run_exit_code, run_status
from phav_validators.realism.check import MIN_VIDEOS, VIEWS, RealismResult
from phav_validators.realism.figures import example_sheet

#: Version of the JSON report's layout; bumped when a field changes meaning.
REPORT_VERSION = 1
#: Flagged videos shown with a frame in the HTML report.
MAX_FRAMES = 6


def report_json(reports: Sequence[DatasetReport]) -> dict[str, Any]:
    """The whole run as one JSON document."""
    status = run_status(reports)
    return {
        "report_version": REPORT_VERSION,
        "phav_version": package_version("phav"),
        "status": status.value,
        "exit_code": run_exit_code(status),
        "datasets": [r.to_json() for r in reports],
    }


def _default(value: Any) -> Any:

    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")


def plain_json(value: Any) -> Any:
    """``value`` in JSON's own types, numpy's included, with every number JSON has none for
    (NaN, ±infinity) as null: what a strict parser reads back."""
    if isinstance(value, dict):
        return {k: plain_json(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [plain_json(v) for v in value]
    if isinstance(value, np.generic | np.ndarray):
        return plain_json(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_json(reports: Sequence[DatasetReport], path: Path) -> None:
    """Write the report atomically (NaN and infinities written as null)."""
    text = json.dumps(plain_json(report_json(reports)), indent=2, sort_keys=True, ensure_ascii=False,
                      allow_nan=False, default=_default)  # fmt: skip
    with atomic_write(path) as tmp:
        tmp.write_text(text + "\n", encoding="utf-8")


def histogram_svg(
    title: str, values: Sequence[Any], observed: Sequence[float], expected: Sequence[float] | None = None
) -> str:
    """Side-by-side bars of observed and expected shares per value (at most 40 values); with
    ``expected`` None, observed bars only, every value shown."""
    if expected is None:
        rows = [(str(v), o, None) for v, o in zip(values, observed, strict=True)][:40]
    else:
        rows = [(str(v), o, e) for v, o, e in zip(values, observed, expected, strict=True) if o > 0 or e > 0][:40]
    if not rows:
        return ""
    bar_w, gap, height, top = 9, 6, 120, 18
    width = max(len(rows) * (2 * bar_w + gap) + 130, 240)  # room for the last rotated label
    peak = max(max(o, e or 0.0) for _, o, e in rows) or 1.0
    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height + top + 100}" '
        'font-family="sans-serif" font-size="10">',
        f'<text x="4" y="12" font-weight="bold">{html.escape(title)}</text>',
    ]
    for i, (label, o, e) in enumerate(rows):
        x = 30 + i * (2 * bar_w + gap)
        for j, (share, colour) in enumerate(((o, "#3b6fb6"), (e, "#e39b2d"))):
            if share is None:
                continue
            h = share / peak * height
            parts.append(f'<rect x="{x + j * bar_w}" y="{top + height - h:.1f}" width="{bar_w - 1}" '
                         f'height="{h:.1f}" fill="{colour}"><title>{html.escape(label)}: '
                         f'{"observed" if j == 0 else "expected"} {share:.2%}</title></rect>')  # fmt: skip
        parts.append(f'<text transform="translate({x + bar_w},{top + height + 6}) rotate(60)">'
                     f"{html.escape(label[:18])}</text>")  # fmt: skip
    parts.append(f'<text x="4" y="{top + 10}">{peak:.0%}</text></svg>')
    return "".join(parts)


def framing_html(framing: FramingResult) -> str:
    """The protagonist's framing: a table per camera and a height histogram per camera."""
    out = [
        "<h3>Protagonist framing</h3><p>Height of the box around the protagonist's visible pixels, as a share "
        "of the frame height, over the frames where it has any pixel (people.parquet <code>bbox2d</code>, "
        "<code>pixels</code>).</p>",
        "<table><tr><th>camera</th><th>videos</th><th>frames</th><th>in view</th><th>Q1</th><th>median</th>"
        "<th>Q3</th><th>median px</th></tr>",
    ]
    for name, g in framing.groups.items():
        q1, q2, q3 = g.quantiles()
        cells = [figure_text(v, ".1%") for v in (g.in_view_share, q1, q2, q3)] + [figure_text(g.median_px, ".0f")]
        out.append(f"<tr><td>{html.escape(name)}</td><td>{g.n_videos}</td><td>{g.n_frames:,}</td>"
                   + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")  # fmt: skip
    out.append("</table>")
    labels = [f"{FRAMING_BINS[b]:.0%}–{FRAMING_BINS[b + 1]:.0%}" for b in range(len(FRAMING_BINS) - 1)]
    for name, g in framing.groups.items():
        title = f"protagonist height, {name} (share of {g.n_frames:,} frames)"
        out.append(histogram_svg(title, labels, [float(x) for x in g.histogram()]))
    return "".join(out)


def _frame_png(shard: str, video_id: str, frame: int) -> str | None:
    """The RGB frame (or the video's first) as a base64 PNG data URL, None if unreadable."""

    first = None
    try:
        for f, arrays in shard_video_frames(shard, video_id):
            first = first if first is not None else arrays["rgb"]
            if f == frame:
                first = arrays["rgb"]
                break
    except OSError:
        return None
    if first is None:
        return None
    return _rgb_png_url(first)


def flagged_pictures(report: DatasetReport) -> dict[str, str]:
    """The frame the HTML report shows of each of the worst flagged videos, as a PNG data URL:
    the one kept in the report (``flagged_pictures``), else read from its shard now."""
    out = {}
    for vid, _, _, _ in report.worst_videos(MAX_FRAMES):
        if vid in report.flagged_frames:
            shard, frame = report.flagged_frames[vid]
            url = report.flagged_pictures.get(vid) or _frame_png(shard, vid, frame)
            if url is not None:
                out[vid] = url
    return out


def _png_url(png: bytes) -> str:
    """PNG bytes as a data URL the page can show inline."""
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def _rgb_png_url(image: np.ndarray) -> str | None:
    """An RGB image (H, W, 3) uint8 as a PNG data URL, None if OpenCV cannot encode it."""
    ok, png = cv2.imencode(".png", np.ascontiguousarray(image[..., ::-1]))
    return _png_url(png.tobytes()) if ok else None


def learnability_html(learn: LearnResult, root: Path) -> list[str]:
    """The confusion matrix, per-class accuracy (worst first) and, for the classes most
    often answered for each other, a middle frame of a clip of each, side by side."""
    esc = html.escape
    url = _png_url(confusion_png(learn.confusion(), learn.classes))
    out = [f"<h3>Learnability: confusion on held-out actors (fused)</h3><img src='{url}'>",
           "<h4>Per class (fused, worst first)</h4><table><tr><th>class</th><th>test clips</th><th>accuracy</th>"
           "<th>most often answered instead</th></tr>"]  # fmt: skip
    for row in learn.per_class():
        instead = f"{row['mistaken_for']} ({row['mistakes']})" if row["mistaken_for"] else ""
        out.append(f"<tr><td>{esc(row['class'])}</td><td>{row['clips']}</td><td>{row['accuracy']:.0%}</td>"
                   f"<td>{esc(instead)}</td></tr>")  # fmt: skip
    out.append("</table>")
    try:
        videos = {v.video_id: v for v in load_manifest(root / "manifest.json").videos}
    except (OSError, ValueError, PhavUserError):
        videos = {}
    figures = []
    for a, b, n in learn.confused_pairs(3):
        if learn.example(a, b) is None:
            a, b = b, a  # show the direction that happened: a clip of a answered b …
        pair = []
        for true, answer in ((a, b), (b, b) if learn.example(b, b) is not None else (b, a)):  # … beside one of b
            key = learn.example(true, answer)
            entry = videos.get(key) if key is not None else None
            image = _frame_png(str(root / entry.shard), key, entry.n_frames // 2) if entry is not None else None
            if image is not None:
                pair.append(f"<figure><img src='{image}' width='255'><figcaption>{esc(key)}: {esc(true)}, "
                            f"answered {esc(answer)}</figcaption></figure>")  # fmt: skip
        if pair:
            figures.append(f"<div><b>{esc(a)} ↔ {esc(b)}</b>: {n} test clips answered as the other<br>"
                           + "".join(pair) + "</div>")  # fmt: skip
    if figures:
        out.append("<h4>Most confused pairs</h4>" + "".join(figures))
    return out


def _figure_cell(fig: Any) -> str:
    if fig is None:
        return "<td></td>"
    interval = "one video" if fig.low is None else f"{figure_text(fig.low, '.2f')}–{figure_text(fig.high, '.2f')}"
    return f"<td>{figure_text(fig.value, '.2f')} <small>({interval}; n {fig.count:,.0f})</small></td>"


def realism_html(result: RealismResult) -> list[str]:
    """The people table per view and per joint, the world table per judge and class (all
    environments, then each), and a few judged frames beside their ground truth."""
    esc = html.escape
    fig = result.figures.get
    models = ", ".join(f"{esc(n)} {h[:12]}" for n, h in sorted(result.models.items()))
    out = [f"<h3>Realism: models trained on real photographs</h3><p>{result.frames} frames of {result.videos} "
           f"videos (seed {result.options.seed}), {result.people} protagonists judged; each figure with its 95 % "
           f"bootstrap interval over videos and its count. Models (sha256): {models}.</p>",
           "<h4>People</h4><table><tr><th>view or action</th><th>found by the detector</th><th>its score</th>"
           "<th>PCK 0.1</th><th>PCK 0.2</th><th>left/right swapped</th></tr>"]  # fmt: skip
    names = ("person_found", "person_score", "person_pck_0.1", "person_pck_0.2", "person_swap")
    actions = sorted(k.split("|")[1] for k, f in result.figures.items()
                     if k.startswith("person_found|action=") and f.videos >= MIN_VIDEOS)  # fmt: skip
    for group in ("all", *(f"view={v}" for v in VIEWS), *actions):
        cells = "".join(_figure_cell(fig(f"{k}|{group}")) for k in names)
        out.append(f"<tr><td>{esc(group.removeprefix('view='))}</td>{cells}</tr>")
    out.append("</table><table><tr><th>joint</th><th>PCK 0.1</th><th>PCK 0.2</th></tr>")
    joints = sorted({k.split("|")[1] for k in result.figures if k.startswith("joint_pck_0.2|")})
    for j in joints:
        out.append(f"<tr><td>{esc(j)}</td>{_figure_cell(fig(f'joint_pck_0.1|{j}'))}"
                   f"{_figure_cell(fig(f'joint_pck_0.2|{j}'))}</tr>")  # fmt: skip
    out.append("</table>")
    for judge in ("pascal_voc", "cityscapes"):
        keys = [k for k in result.figures if k.startswith(f"iou|{judge}|")]
        ours = sorted({k.split("|")[2] for k in keys})
        envs = sorted({k.split("|")[3] for k in keys if k.split("|")[3].startswith("environment=")})
        if not ours:
            continue
        head = "".join(f"<th>IoU {esc(e.removeprefix('environment='))}</th>" for e in envs)
        out.append(f"<h4>World: {esc(judge)}</h4><table><tr><th>our class</th><th>IoU</th><th>recall</th>{head}</tr>")
        for c in ours:
            cells = "".join(_figure_cell(fig(f"iou|{judge}|{c}|{e}")) for e in envs)
            out.append(f"<tr><td>{esc(c)}</td>{_figure_cell(fig(f'iou|{judge}|{c}|all'))}"
                       f"{_figure_cell(fig(f'recall|{judge}|{c}|all'))}{cells}</tr>")  # fmt: skip
        out.append("</table>")
    if fig("cityscapes_miou") is not None:
        m = fig("cityscapes_miou")
        out.append(f"<p>Cityscapes mIoU over its classes present: {m.said()}.")
        for kind in ("weather", "day_phase", "light"):
            parts = [f"{k.split('=')[1]} {figure_text(result.figures[k].value, '.2f')}" for k in sorted(result.figures)
                     if k.startswith(f"cityscapes_miou|{kind}=")]  # fmt: skip
            if parts:
                out.append(f" By {kind.replace('_', ' ')}: {', '.join(parts)}.")
        out.append("</p>")
    if result.examples:
        out.append(
            "<h4>Judged frames</h4><p>The frame with our box and joints (white, green), the detector's person region "
            "(yellow) and the landmark model's joints (red); then per segmenter, what it should answer and what it "
            "answered (dark grey: not judged).</p>"
        )
        for ex in result.examples:
            sheet = example_sheet(ex, JUDGE_CLASSES)
            out.append(f"<figure><img src='{_rgb_png_url(sheet)}'><figcaption>{esc(ex['video'])} frame "
                       f"{ex['frame']:05d}</figcaption></figure>")  # fmt: skip
    return out


def report_html(reports: Sequence[DatasetReport]) -> str:
    esc = html.escape
    out = [
        "<!doctype html><html><head><meta charset='utf-8'><title>phav-validate report</title><style>",
        "body{font-family:sans-serif;margin:2em;max-width:1200px}table{border-collapse:collapse}",
        "td,th{border:1px solid #ccc;padding:3px 8px;text-align:left;vertical-align:top}",
        ".pass{color:#1a7f37}.warn{color:#b58100}.fail{color:#c00;font-weight:bold}.skip{color:#888}",
        "figure{display:inline-block;margin:6px}</style></head><body>",
        f"<h1>phav-validate report</h1><p>phav {esc(package_version('phav'))}. Legend: "
        "<span style='color:#3b6fb6'>■ observed</span> <span style='color:#e39b2d'>■ expected from θ</span></p>",
    ]
    for r in reports:
        theta = f"θ {esc(r.theta['name'])} {esc(r.theta['hash'][:12])}…" if r.theta else "no θ"
        out.append(f"<h2>{esc(r.source)} — <span class='{r.status.value}'>{r.status.value.upper()}</span></h2>")
        out.append(f"<p>{r.size}; {theta}</p>")
        out.append("<table><tr><th>check</th><th>status</th><th>s</th><th>result</th><th>findings</th></tr>")
        for c in r.checks:
            counts = ", ".join(f"{k.value} × {n}" for k, n in sorted(c.report.counts.items()))
            result = esc(c.summary) + "".join(f"<br><small>note: {esc(n)}</small>" for n in c.report.all_notes())
            out.append(f"<tr><td>{c.name}</td><td class='{c.status.value}'>{c.status.value}</td>"
                       f"<td>{c.seconds:.1f}</td><td>{result}</td><td>{esc(counts)}</td></tr>")  # fmt: skip
        out.append("</table>")
        if any(c.report.findings for c in r.checks):
            out.append("<h3>Findings</h3><table><tr><th>check</th><th>reason</th><th>where</th><th>message</th></tr>")
            # Every finding the JSON lists (a check keeps MAX_PER_REASON per reason; its notes count the rest).
            for c in r.checks:
                for f in c.report.findings:
                    where = " ".join(x for x in (f.file, f.video_id) if x)
                    out.append(f"<tr><td>{c.name}</td><td class='{f.severity}'>{f.reason.value}</td>"
                               f"<td>{esc(where)}</td><td>{esc(f.message)}</td></tr>")  # fmt: skip
            out.append("</table>")
        if r.distribution is not None:
            out.append("<h3>Observed against expected</h3>")
            for s in r.distribution.summaries:
                n = int(s.observed.sum())
                shares = [float(o) / max(n, 1) for o in s.observed]
                title = f"{s.variable} ({s.applies_to}, n = {n})"
                out.append(histogram_svg(title, s.values, shares, [float(e) for e in s.expected]))
        if r.framing is not None and r.framing.groups:
            out.append(framing_html(r.framing))
        frames = []
        pictures = flagged_pictures(r)
        for vid, failing, warning, reasons in r.worst_videos(MAX_FRAMES):
            if vid in pictures:
                frame = r.flagged_frames[vid][1]
                frames.append(f"<figure><img src='{pictures[vid]}' width='340'><figcaption>{esc(vid)} frame "
                              f"{frame:05d}: {esc(', '.join(reasons))}</figcaption></figure>")  # fmt: skip
            else:  # listed as the JSON's worst_videos lists it: no frame of it could be read
                frames.append(f"<p>{esc(vid)} ({failing} fail, {warning} warn): {esc(', '.join(reasons))}; "
                              "no frame of it to show</p>")  # fmt: skip
        if frames:
            out.append("<h3>Flagged videos</h3>" + "".join(frames))
        if r.learnability is not None:
            out += learnability_html(r.learnability, Path(r.root or r.source))
        if r.realism is not None:
            out += realism_html(r.realism)
    out.append("</body></html>")
    return "\n".join(out)


def write_html(reports: Sequence[DatasetReport], path: Path) -> None:
    """Write the HTML report atomically."""
    text = report_html(reports)
    with atomic_write(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
