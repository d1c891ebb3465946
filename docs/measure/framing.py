"""How large and how often in view the camera films the protagonist (docs/framing.md).

``measure``: samples θ's recipes for ``--seed`` in dataset order, keeps the first
``--videos`` whose camera is ``--camera`` (phav-v1's kite videos, say), simulates each and
renders its labelled pass only (the instance mask and the metadata rows exactly as
``phav generate`` writes them; no RGB, no supersampling, no PNG), then measures the
protagonist's framing with ``phav_validators.framing`` (the numbers ``phav stats`` and
``phav-validate`` show for a generated dataset) and which frames show its head and hands.
Writes a JSON summary with one row per video, and the protagonist's rows beside it
(.parquet). ``plot``: the height histograms of several summaries side by side, as a PNG.
``frames``: the middle frame of the first few such videos, side by side (runs on an older
checkout too: ``PYTHONPATH=<checkout>``).

    .venv/bin/python docs/measure/framing.py measure --theta phav-v1 --camera kite --videos 100 \\
        --json /tmp/framing-after.json
    git show 13828e9:phav_spec/presets/phav-v1.yaml > /tmp/phav-v1-before.yaml    # the ranges before
    .venv/bin/python docs/measure/framing.py measure --theta /tmp/phav-v1-before.yaml \\
        --json /tmp/framing-before.json
    .venv/bin/python docs/measure/framing.py plot /tmp/framing-before.json /tmp/framing-after.json \\
        --out docs/images/framing-kite.png
"""

from __future__ import annotations

import argparse
import json
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from phav_generator.physics.plan.scene import plan_scene
from phav_generator.physics.simulate import simulate_plan
from phav_generator.render.annotations import MetadataBuilder
from phav_generator.render.context import gl_context
from phav_generator.render.video import scene_renderer
from phav_generator.sampling import RecipeSampler
from phav_spec.recipe import Recipe, parse_recipe
from phav_spec.theta import load_theta
from phav_spec.vocab import PIXEL_CLASSES

#: Body parts whose visibility the close-up camera is judged by (pixels of the protagonist).
PARTS = ("head", "left_hand", "right_hand")
_ctx = None


def _rows(recipe_json: str) -> tuple[dict, np.ndarray, float, float]:
    """One video's protagonist rows (video_id, person_id, pixels, bbox2d), its pixels of the
    ``PARTS`` classes per frame, and its simulate / render seconds."""
    global _ctx
    if _ctx is None:
        _ctx = gl_context("llvmpipe")
    recipe = parse_recipe(recipe_json)
    t0 = time.perf_counter()
    tr = simulate_plan(plan_scene(recipe), keep_state=False)
    t1 = time.perf_counter()
    cols: dict[str, list] = {"video_id": [], "person_id": [], "pixels": [], "bbox2d": []}
    parts = np.zeros((tr.n_frames, len(PARTS)), dtype=np.int64)  # protagonist pixels per part class
    ids = np.array([PIXEL_CLASSES[p].class_id for p in PARTS])
    with scene_renderer(recipe, tr, _ctx, supersample=1) as renderer:
        meta = MetadataBuilder(recipe, tr)
        for f in range(tr.n_frames):
            labels = renderer.render_labels(f, tr.cam_to_world[f], tr.cam_to_world[f + 1], tr.intrinsics)
            row = next(r for r in meta.people_rows(f, labels) if r["person_id"] == 0)
            for k in cols:
                cols[k].append(row[k])
            mine = labels.class_id[labels.instance == 1]
            parts[f] = (mine[:, None] == ids).sum(axis=0)
    return cols, parts, t1 - t0, time.perf_counter() - t1


def _select(theta: str, camera: str, videos: int, seed: int) -> list[Recipe]:
    sampler = RecipeSampler(load_theta(theta))
    out, i = [], 0
    while len(out) < videos:
        r = sampler.sample(seed, i)
        if camera in ("all", r.camera.kind):
            out.append(r)
        i += 1
    return out


def _describe(r: Recipe) -> dict:
    c = r.camera
    s = c.springs
    return {
        "video_id": r.video_id, "action": r.action, "environment": r.environment.name, "frames": r.n_frames,
        "fov_deg": c.fov_deg, "distance_m": c.distance_m, "height_m": c.height_m,
        "ct_min_distance_m": s.ct_min_distance_m if s else None,
        "tp_min_distance_m": s.tp_min_distance_m if s else None,
        "ct_spring_strength": s.ct_spring_strength if s else None,
        "tp_spring_strength": s.tp_spring_strength if s else None,
        "impulse": c.impulse.strength if c.impulse else None,
    }  # fmt: skip


def measure(args: argparse.Namespace) -> None:
    from phav_validators.framing import VideoFrame, measure_framing

    start = time.perf_counter()
    recipes = _select(args.theta, args.camera, args.videos, args.seed)
    jsons = [r.model_dump_json() for r in recipes]
    if args.workers > 1:
        with ProcessPoolExecutor(args.workers) as pool:
            results = list(pool.map(_rows, jsons))
    else:
        results = [_rows(j) for j in jsons]
    cols: dict[str, list] = {"video_id": [], "person_id": [], "pixels": [], "bbox2d": []}
    for c, _, _, _ in results:
        for k in cols:
            cols[k] += c[k]
    table = pa.table(cols)
    pq.write_table(table, Path(args.json).with_suffix(".parquet"))  # the rows, for a closer look
    info = {r.video_id: VideoFrame(r.camera.kind, r.video.height) for r in recipes}
    result = measure_framing(table, info)
    per_video = []
    seen = np.zeros(4)  # frames with the head, a hand, both hands, head and both hands in view
    for r, (c, parts, sim_s, render_s) in zip(recipes, results, strict=True):
        one = measure_framing(pa.table(c), {r.video_id: info[r.video_id]}).groups["all"]
        head, hands = parts[:, 0] > 0, parts[:, 1:] > 0
        both = hands.all(axis=1)
        seen += [head.sum(), hands.any(axis=1).sum(), both.sum(), (head & both).sum()]
        per_video.append({**_describe(r), "median": one.median, "median_px": one.median_px,
                          "in_view_share": one.in_view_share, "head_share": float(head.mean()),
                          "a_hand_share": float(hands.any(axis=1).mean()), "both_hands_share": float(both.mean()),
                          "simulate_s": sim_s, "render_s": render_s})  # fmt: skip
    wall = time.perf_counter() - start
    summary = {
        "theta": args.theta, "theta_hash": load_theta(args.theta).hash, "camera": args.camera, "seed": args.seed,
        "videos": len(recipes), "wall_s": wall, "workers": args.workers, "groups": result.to_json(),
        "video_median_share_ge_35": float(np.mean(result.groups["all"].video_medians >= 0.35)),
        "parts_in_view": dict(zip(("head", "a_hand", "both_hands", "head_and_both_hands"),
                                  (seen / max(result.groups["all"].n_frames, 1)).tolist(), strict=True)),
        "per_video": per_video,
    }  # fmt: skip
    Path(args.json).write_text(json.dumps(summary, indent=1) + "\n", encoding="utf-8")
    g = result.groups["all"]
    q1, q2, q3 = g.quantiles()
    p1, p2, p3 = g.quantiles(px=True)
    print(f"{len(recipes)} videos, {g.n_frames} frames, {wall:.0f} s; protagonist in view {g.in_view_share:.1%}; "
          f"height quartiles {p1:.0f} / {p2:.0f} / {p3:.0f} px = {q1:.1%} / {q2:.1%} / {q3:.1%}")  # fmt: skip
    print("frames with in view: " + ", ".join(f"{k} {v:.1%}" for k, v in summary["parts_in_view"].items()))


def plot(args: argparse.Namespace) -> None:
    """Grouped bars: share of frames per 10 % height bin, one colour per summary (ASCII text:
    the default font has no en dash or degree sign)."""
    from PIL import Image, ImageDraw, ImageFont

    from phav_validators.framing import FRAMING_BINS

    runs = [json.loads(Path(p).read_text(encoding="utf-8")) for p in args.summaries]
    labels = args.label or [Path(p).stem for p in args.summaries]
    colours = [(227, 155, 45), (59, 111, 182), (60, 160, 90), (180, 60, 60)]
    w, h, left, top, bottom = 900, 420, 70, 50, 70
    img = Image.new("RGB", (w, h), "white")
    d = ImageDraw.Draw(img)
    font = ImageFont.load_default(size=14)
    small = ImageFont.load_default(size=12)
    bins = len(FRAMING_BINS) - 1
    shares = [np.array(r["groups"][args.group]["histogram"]["shares"]) for r in runs]
    peak = max(0.05, max(float(s.max()) for s in shares))
    peak = float(np.ceil(peak * 20) / 20)
    plot_w, plot_h = w - left - 20, h - top - bottom
    for k in range(round(peak * 20) + 1):
        y = top + plot_h - k * 0.05 / peak * plot_h
        d.line([(left, y), (left + plot_w, y)], fill=(225, 225, 225))
        d.text((left - 8, y), f"{k * 5}%", fill="black", font=small, anchor="rm")
    group_w = plot_w / bins
    bar_w = group_w * 0.8 / len(runs)
    for b in range(bins):
        x0 = left + b * group_w + group_w * 0.1
        for i, s in enumerate(shares):
            bh = s[b] / peak * plot_h
            d.rectangle([x0 + i * bar_w, top + plot_h - bh, x0 + (i + 1) * bar_w - 2, top + plot_h], fill=colours[i])
        d.text((left + (b + 0.5) * group_w, top + plot_h + 6), f"{b * 10}-{(b + 1) * 10}%", fill="black",
               font=small, anchor="ma")  # fmt: skip
    d.line([(left, top + plot_h), (left + plot_w, top + plot_h)], fill="black")
    d.text((left + plot_w / 2, h - 30), "protagonist height (box of its visible pixels) / frame height", fill="black",
           font=font, anchor="ma")  # fmt: skip
    d.text((10, 12), args.title, fill="black", font=font)
    x = left
    for i, (r, label) in enumerate(zip(runs, labels, strict=True)):
        g = r["groups"][args.group]
        text = (f"{label}: median {g['height_quartiles_px'][1]:.0f} px ({g['height_quartiles'][1]:.0%}), "
                f"in view {g['in_view_share']:.1%}")  # fmt: skip
        d.rectangle([x, 32, x + 12, 44], fill=colours[i])
        d.text((x + 18, 38), text, fill="black", font=small, anchor="lm")
        x += int(d.textlength(text, font=small)) + 40
    img.save(args.out)
    print(f"wrote {args.out}")


def frames(args: argparse.Namespace) -> None:
    """The middle frame (final RGB) of each of the first ``--videos`` videos, the protagonist's
    box drawn, in one row. Needs only the generator, so it also runs on an older checkout."""
    from PIL import Image, ImageDraw

    from phav_generator.render.video import render_video

    global _ctx
    _ctx = _ctx or gl_context("llvmpipe")
    tiles = []
    for r in _select(args.theta, args.camera, args.videos, args.seed):
        tr = simulate_plan(plan_scene(r), keep_state=False)
        mid = tr.n_frames // 2
        for rf in render_video(r, tr, ctx=_ctx):
            if rf.index == mid:
                im = Image.fromarray(rf.modalities["rgb"])
                box = next(p["bbox2d"] for p in rf.people if p["person_id"] == 0)
                if np.isfinite(box).all():
                    ImageDraw.Draw(im).rectangle([box[0], box[1], box[2] - 1, box[3] - 1], outline=(255, 60, 60))
                ImageDraw.Draw(im).text((4, 4), f"{r.video_id} {r.action}", fill=(255, 255, 0))
                tiles.append(im)
                break
    sheet = Image.new("RGB", (sum(t.width for t in tiles), max(t.height for t in tiles)))
    x = 0
    for t in tiles:
        sheet.paste(t, (x, 0))
        x += t.width
    sheet.save(args.out)
    print(f"wrote {args.out}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    m = sub.add_parser("measure")
    m.add_argument("--theta", default="phav-v1")
    m.add_argument("--camera", default="kite", help="kite, indoors, closeup, static or all")
    m.add_argument("--videos", type=int, default=100)
    m.add_argument("--seed", type=int, default=0)
    m.add_argument("--workers", type=int, default=1)
    m.add_argument("--json", required=True)
    p = sub.add_parser("plot")
    p.add_argument("summaries", nargs="+")
    p.add_argument("--label", action="append", help="one per summary, in order (default: file names)")
    p.add_argument("--group", default="all")
    p.add_argument("--title", default="Protagonist height in phav-v1 kite videos (share of all frames)")
    p.add_argument("--out", required=True)
    f = sub.add_parser("frames")
    f.add_argument("--theta", default="phav-v1")
    f.add_argument("--camera", default="kite")
    f.add_argument("--videos", type=int, default=4)
    f.add_argument("--seed", type=int, default=0)
    f.add_argument("--out", required=True)
    args = parser.parse_args()
    os.environ.setdefault("LP_NUM_THREADS", "1")
    {"measure": measure, "plot": plot, "frames": frames}[args.command](args)


if __name__ == "__main__":
    main()
