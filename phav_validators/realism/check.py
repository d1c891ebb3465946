"""The realism check: models trained on real photographs judge a seeded sample of frames.

People: BlazePose's detector on the whole frame (does it find the protagonist?) and its
landmark model on an upright crop around the protagonist's box (does it land the joints on
``joints2d``?). World: two segmenters label every pixel, and each of our pixel classes is
scored against the class a person would name it by (``phav_spec.judge_classes``). Every
figure is a ratio of sums over videos with a 95 % bootstrap interval over videos (frames of
one video are not independent). A figure never fails a dataset unless a minimum is asked.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from phav_spec.clips import ClipReader
from phav_spec.errors import PhavUserError
from phav_spec.judge_classes import JUDGE_CLASSES, JudgeClasses
from phav_spec.metadata import JOINT_ORDER
from phav_spec.recipe_table import read_recipe_table
from phav_spec.scene import ENVIRONMENT_SCENES
from phav_spec.seeding import stream
from phav_spec.vocab import PIXEL_CLASSES, PixelGroup
from phav_validators.checks.scan import class_lut, rgb_code
from phav_validators.findings import CheckResult, Finding, ProgressFactory, Reason, Report
from phav_validators.realism.judges import BLAZEPOSE_JOINTS, JUDGE_MODELS, Judges, load_judges, upright_crop

_PERSON_GROUPS = (PixelGroup.HUMAN_PARTS, PixelGroup.HUMAN_JOINTS)
_J = {name: i for i, name in enumerate(JOINT_ORDER)}
_MIRROR = {n: n.replace("left", "right") if n.startswith("left") else n.replace("right", "left")
           for n in BLAZEPOSE_JOINTS}  # fmt: skip
#: Camera views of a person: the angle between where it faces and where the camera is.
VIEWS = ("front", "side", "back")
#: An action's figures are shown from at least this many videos (35 actions share a sample).
MIN_VIDEOS = 5
#: Bootstrap resamples of the videos for each interval.
RESAMPLES = 1000


@dataclass(frozen=True)
class RealismOptions:
    """Settings of the realism check."""

    #: Frames judged, drawn with ``seed`` from every video's frames (the segmenters take
    #: ~0.1 s a frame).
    frames: int = 200
    #: A protagonist is judged when its box is at least this tall (pixels).
    min_person_px: float = 64.0
    #: Where the model files are (None: the ones shipped with phav).
    models_dir: Path | None = None
    threads: int = 1
    seed: int = 0
    #: Figure name → the least value that passes (``--realism-min person_pck_0.2=0.9``).
    minimums: Mapping[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class Figure:
    """A ratio of sums over videos, its 95 % bootstrap interval and what it counts."""

    value: float
    low: float | None  # None from one video: a bootstrap of one is no interval
    high: float | None
    count: float
    videos: int

    def to_json(self) -> dict[str, Any]:
        ci = None if self.low is None or self.high is None else [round(self.low, 4), round(self.high, 4)]
        return {"value": round(self.value, 4), "ci95": ci, "count": round(self.count, 3), "videos": self.videos}

    def said(self) -> str:
        """The value and its interval in words: ``0.36 (0.32–0.41)``, or ``0.36 (one video)``."""
        if self.low is None or self.high is None:
            return f"{self.value:.2f} (one video)"
        return f"{self.value:.2f} ({self.low:.2f}–{self.high:.2f})"


def _resamples(seed: int, videos: Sequence[str]) -> np.ndarray | None:
    """The bootstrap's resamples of ``videos`` (RESAMPLES × n indices), drawn once per set of
    videos: figures over the same videos share them, so one ratio reported under two names
    has one interval. None for a single video."""
    if len(videos) < 2:
        return None
    key = hashlib.sha256("\n".join(videos).encode()).hexdigest()[:16]
    return stream(seed, f"realism/bootstrap/{key}").integers(0, len(videos), (RESAMPLES, len(videos)))


class Tally:
    """Per-video numerators and denominators of ratios named by key. A ratio is reported once
    something it is about was seen (``present``): a class's IoU counts the judge's false
    answers in every frame, but is a figure only where the class is in some frame."""

    def __init__(self) -> None:
        self.parts: dict[str, dict[str, list[float]]] = {}
        self.present: set[str] = set()
        #: The videos whose frames show what each key is about (a bootstrap resample of
        #: videos none of which shows a class leaves the class out, as the figure does).
        self.shown: dict[str, set[str]] = {}

    def add(self, key: str, video: str, num: float, den: float, *, present: bool = True) -> None:
        cell = self.parts.setdefault(key, {}).setdefault(video, [0.0, 0.0])
        cell[0] += num
        cell[1] += den
        if present:
            self.present.add(key)
            self.shown.setdefault(key, set()).add(video)

    def figure(self, key: str, seed: int) -> Figure | None:
        """The ratio of ``key`` over every video, with a bootstrap over videos (None when
        nothing was counted or nothing it is about was seen). A resample of videos none of
        which shows what ``key`` is about gives no figure, as the whole would not, and is left
        out of the interval (it scored 0 through false answers elsewhere)."""
        cells = self.parts.get(key, {})
        videos = sorted(v for v, (_, d) in cells.items() if d > 0)
        if not videos or key not in self.present:
            return None
        num = np.array([cells[v][0] for v in videos])
        den = np.array([cells[v][1] for v in videos])
        shown = np.array([v in self.shown.get(key, ()) for v in videos])
        value = float(num.sum() / den.sum())
        draws = _resamples(seed, videos)
        if draws is None:
            return Figure(value, None, None, float(den.sum()), 1)
        ratios = num[draws].sum(axis=1) / np.maximum(den[draws].sum(axis=1), 1e-12)
        low, high = np.percentile(ratios[shown[draws].any(axis=1)], [2.5, 97.5])
        return Figure(value, float(low), float(high), float(den.sum()), len(videos))

    def figures(self, seed: int) -> dict[str, Figure]:
        return {k: f for k in sorted(self.parts) if (f := self.figure(k, seed)) is not None}


def view_of(person: Mapping[str, Any], camera: Mapping[str, Any]) -> str | None:
    """front, side or back: where the camera stands around the person, from the hips' line
    (the person's left × up is where it faces) and the camera's position (world +Z up)."""
    joints = np.array(person["joints3d"], dtype=float).reshape(-1, 3)
    left = joints[_J["left_hip"]] - joints[_J["right_hip"]]
    facing = np.cross(left, [0.0, 0.0, 1.0])[:2]
    pose = np.array(camera["cam_to_world"], dtype=float).reshape(4, 4)
    to_camera = pose[:2, 3] - (joints[_J["left_hip"]] + joints[_J["right_hip"]])[:2] / 2
    norms = np.linalg.norm(facing) * np.linalg.norm(to_camera)
    if not np.isfinite(norms) or norms == 0:
        return None
    angle = math.degrees(math.acos(float(np.clip(facing @ to_camera / norms, -1.0, 1.0))))
    return VIEWS[0] if angle < 45 else VIEWS[1] if angle <= 135 else VIEWS[2]


def sample_frames(reader: ClipReader, n: int, seed: int) -> dict[str, list[int]]:
    """``n`` frames (all when fewer) drawn with ``seed`` from every video's frames, by video."""
    return draw_frames(((v, reader.n_frames[v]) for v in reader.video_ids), n, seed)


def draw_frames(videos: Iterable[tuple[str, int]], n: int, seed: int) -> dict[str, list[int]]:
    """``sample_frames`` on (video id, frame count) pairs in the dataset's video order: the
    frames the check judges, known before the videos are rendered."""
    pairs = [(v, f) for v, count in videos for f in range(count)]
    chosen = stream(seed, "realism/frames").permutation(len(pairs))[: min(n, len(pairs))]
    out: dict[str, list[int]] = {}
    for i in sorted(chosen):
        out.setdefault(pairs[i][0], []).append(pairs[i][1])
    return out


#: Weathers of the light the street model was trained in (Cityscapes: daytime, fair weather).
FAIR_WEATHERS = ("clear", "overcast")


def conditions_of(weather: str, day_phase: str) -> tuple[str, ...]:
    """A video's condition groups for the world's figures: its weather and day phase, and
    ``light=fair_day`` in clear or overcast daytime. Fog, rain and dusk hide what a judge
    trained on fair daytime streets knows; the fair-day figures show the looks alone."""
    fair = weather in FAIR_WEATHERS and day_phase == "day"
    return (f"weather={weather}", f"day_phase={day_phase}", *(("light=fair_day",) if fair else ()))


def judge_person(judges: Judges, tally: Tally, video: str, rgb: np.ndarray, person: Mapping[str, Any],
                 groups: tuple[str, ...]) -> dict[str, Any]:  # fmt: skip
    """Detector and landmarks on one person; counts added under each of ``groups`` (e.g.
    ``all``, ``view=back``, ``action=walk``). Returns what was found, for the examples."""
    x0, y0, x1, y1 = person["bbox2d"]
    height = y1 - y0
    joints = np.array(person["joints2d"], dtype=float).reshape(-1, 2)
    detections = judges.detector.detections(rgb)
    hits = [d for d in detections if x0 <= d.hip_centre[0] <= x1 and y0 <= d.hip_centre[1] <= y1]
    hips = joints[[_J["left_hip"], _J["right_hip"]]].mean(axis=0)
    shoulders = joints[[_J["left_shoulder"], _J["right_shoulder"]]].mean(axis=0)
    answer = judges.landmarks.landmarks(rgb, upright_crop((x0, y0, x1, y1), hips, shoulders))
    seen = [n for n in BLAZEPOSE_JOINTS if person["visible"][_J[n]] and np.all(np.isfinite(joints[_J[n]]))]
    error = {n: float(np.linalg.norm(np.array(answer.joints[n]) - joints[_J[n]])) / height for n in seen}
    mirrored = {n: float(np.linalg.norm(np.array(answer.joints[_MIRROR[n]]) - joints[_J[n]])) / height for n in seen}
    sided = [n for n in seen if n != _MIRROR[n]]
    # A swap: the mirrored labelling fits at least twice as well, and the direct one misses.
    direct = float(np.mean([error[n] for n in sided])) if sided else math.nan
    swapped = bool(sided) and direct > 0.1 and float(np.mean([mirrored[n] for n in sided])) < direct / 2
    for g in groups:
        tally.add(f"person_found|{g}", video, float(bool(hits)), 1.0)
        tally.add(f"person_score|{g}", video, hits[0].score if hits else 0.0, 1.0)
        tally.add(f"person_pck_0.1|{g}", video, sum(e < 0.1 for e in error.values()), len(error))
        tally.add(f"person_pck_0.2|{g}", video, sum(e < 0.2 for e in error.values()), len(error))
        if sided:
            tally.add(f"person_swap|{g}", video, float(swapped), 1.0)
    for n, e in error.items():
        tally.add(f"joint_pck_0.1|{n}", video, float(e < 0.1), 1.0)
        tally.add(f"joint_pck_0.2|{n}", video, float(e < 0.2), 1.0)
    return {"found": hits[0] if hits else None, "landmarks": answer, "error": error}


@cache
def judged_groups(judge_name: str) -> dict[str, dict[str, list[int]]]:
    """Judge class → our classes judged as it → their class ids; a person's parts and joints
    count as one class, ``person`` (a body is one object, to us as to the judge)."""
    judge = JUDGE_CLASSES[judge_name]
    out: dict[str, dict[str, list[int]]] = {}
    for name, info in PIXEL_CLASSES.items():
        m = judge.judged_as.get(name)
        if m is None:
            continue
        ours = "person" if info.group in _PERSON_GROUPS else name
        out.setdefault(m, {}).setdefault(ours, []).append(info.class_id)
    return {m: out[m] for m in sorted(out)}


def judge_world(labels: np.ndarray, classes: np.ndarray, judge: JudgeClasses, tally: Tally, video: str,
                groups: tuple[str, ...]) -> None:  # fmt: skip
    """IoU and recall of each of our classes against what ``judge`` should call it.

    Our class c judged as m: its IoU is |c ∩ m| / |c ∪ (m outside every class judged as m)|,
    so that a tree judged as vegetation is not blamed for the hedge beside it. Per judge class,
    the plain IoU against the union of our classes judged as it (mIoU over those present).
    Both are sums over the whole sample, as the judges' own benchmarks pool their confusion
    matrices: the judge's m on a frame without any of our m counts against m too. The judge's
    answers merged into m (``JudgeClasses.merged``) count as m; where the judge's own
    benchmark leaves out what it has no class for (``JudgeClasses.void_unjudged``), its
    answers on our classes it does not judge count nowhere."""
    judged = judged_groups(judge.judge)
    scored = None
    if judge.void_unjudged:
        scored = np.isin(classes, [i for ours in judged.values() for ids in ours.values() for i in ids])
    for m, ours in judged.items():
        said = np.isin(labels, judge.answer_ids(m))
        if scored is not None:
            said &= scored
        truth = np.isin(classes, [i for ids in ours.values() for i in ids])
        extra = float((said & ~truth).sum())
        shown = bool(truth.any())
        if shown or extra:
            for g in groups:
                tally.add(f"class_iou|{judge.judge}|{m}|{g}", video, float((said & truth).sum()),
                          float(truth.sum()) + extra, present=shown)  # fmt: skip
        for c, ids in ours.items():
            mask = np.isin(classes, ids)
            n = int(mask.sum())
            if n == 0 and not extra:
                continue
            hit = float((said & mask).sum())
            for g in groups:
                tally.add(f"iou|{judge.judge}|{c}|{g}", video, hit, n + extra, present=n > 0)
                if n:
                    tally.add(f"recall|{judge.judge}|{c}|{g}", video, hit, n)


@dataclass
class RealismResult:
    """Every figure of a realism run by key, and what judged."""

    figures: dict[str, Figure]
    frames: int
    people: int
    videos: int
    models: dict[str, str]
    options: RealismOptions
    examples: list[dict[str, Any]] = field(default_factory=list)

    def get(self, key: str) -> Figure | None:
        return self.figures.get(key)

    def to_json(self) -> dict[str, Any]:
        return {
            "frames": self.frames, "people": self.people, "videos": self.videos, "seed": self.options.seed,
            "models": {n: {"file": JUDGE_MODELS[n].file, "sha256": h, "trained_on": JUDGE_MODELS[n].trained_on}
                       for n, h in self.models.items()},
            "figures": {k: f.to_json() for k, f in self.figures.items()},
        }  # fmt: skip


#: The headline figures ``--realism-min`` can ask for, and how each reads from the result.
HEADLINES: dict[str, str] = {
    "person_found": "person_found|all",
    "person_pck_0.1": "person_pck_0.1|all",
    "person_pck_0.2": "person_pck_0.2|all",
    "voc_person_iou": "class_iou|pascal_voc|person|all",
    "cityscapes_miou": "cityscapes_miou",
}


def parse_minimums(text: str | None) -> dict[str, float]:
    """``person_pck_0.2=0.9,voc_person_iou=0.5`` → {name: minimum}; names from HEADLINES."""
    out: dict[str, float] = {}
    for item in (text or "").split(","):
        if not item.strip():
            continue
        name, _, value = item.partition("=")
        name = name.strip()
        if name not in HEADLINES:
            raise PhavUserError(f"unknown figure {name!r}; choose from {', '.join(HEADLINES)}", field="--realism-min")
        if name in out:
            raise PhavUserError(f"{name} is given twice", field="--realism-min")
        try:
            out[name] = float(value)
        except ValueError:
            raise PhavUserError(f"{name}: {value!r} is not a number", field="--realism-min") from None
        if not math.isfinite(out[name]):  # nan: no figure is ever below it
            raise PhavUserError(f"{name}: {value.strip()!r} is not a finite number", field="--realism-min")
    return out


def cityscapes_miou(tally: Tally, seed: int, group: str = "all") -> Figure | None:
    """Cityscapes mIoU over the judge classes present in ``group``: the mean of their IoUs,
    its interval from the same bootstrap draw of videos for every class."""
    keys = [k for k in sorted(tally.parts)
            if k.startswith("class_iou|cityscapes|") and k.endswith(f"|{group}") and k in tally.present]  # fmt: skip
    videos = sorted({v for k in keys for v, (_, d) in tally.parts[k].items() if d > 0})
    if not keys or not videos:
        return None
    num = np.array([[tally.parts[k].get(v, [0.0, 0.0])[0] for v in videos] for k in keys])
    den = np.array([[tally.parts[k].get(v, [0.0, 0.0])[1] for v in videos] for k in keys])
    shown = np.array([[v in tally.shown.get(k, ()) for v in videos] for k in keys])

    def mean_iou(sel: np.ndarray) -> float:
        """The figure over the videos ``sel``: its classes are those they show (a class's
        false answers elsewhere give it a denominator, not a place in the mean)."""
        d = den[:, sel].sum(axis=1)
        kept = (d > 0) & shown[:, sel].any(axis=1)
        return float(np.mean(num[:, sel].sum(axis=1)[kept] / d[kept])) if kept.any() else math.nan

    value = mean_iou(np.arange(len(videos)))
    draws = _resamples(seed, videos)
    if draws is None:
        return Figure(value, None, None, float(len(keys)), 1)
    low, high = np.nanpercentile([mean_iou(d) for d in draws], [2.5, 97.5])
    return Figure(value, float(low), float(high), float(len(keys)), len(videos))


def run_realism(root: Path, opts: RealismOptions, *, progress: ProgressFactory | None = None) -> RealismResult:
    """Judge a seeded sample of a dataset directory's frames."""
    judges = load_judges(opts.models_dir, opts.threads)
    reader = ClipReader(root)
    table = read_recipe_table(root / "recipes.parquet")
    actions = dict(zip(table.column("video_id"), table.column("action"), strict=True))
    environments = dict(zip(table.column("video_id"), table.column("environment"), strict=True))
    weathers, phases = table.column("weather"), table.column("day_phase")
    conditions = {v: conditions_of(w, d) for v, w, d in zip(table.column("video_id"), weathers, phases, strict=True)}
    chosen = sample_frames(reader, opts.frames, opts.seed)
    advance = progress("realism: judging frames", sum(len(f) for f in chosen.values())) if progress else None
    lut = class_lut()[0]
    tally = Tally()
    people = 0
    examples: list[dict[str, Any]] = []
    try:
        for video, frames in chosen.items():
            clip = reader.read(video, frames, ("rgb", "semantic", "people", "camera"))
            env = environments[video]
            for k, f in enumerate(frames):
                rgb = clip["rgb"][k]
                classes = lut[rgb_code(clip["semantic"][k])]
                where = ("all", f"environment={env}", *conditions[video])
                voc = judges.segmenters["pascal_voc"].labels(rgb)
                judge_world(voc, classes, judges.segmenters["pascal_voc"].classes, tally, video, where)
                city = None
                if not ENVIRONMENT_SCENES[env].indoor:  # a street-scene model: outdoors only
                    city = judges.segmenters["cityscapes"].labels(rgb)
                    judge_world(city, classes, judges.segmenters["cityscapes"].classes, tally, video, where)
                person = next((p for p in clip["people"][k] if p["role"] == "protagonist"), None)
                judged = None
                if person is not None and person["bbox2d"][0] is not None:
                    box = person["bbox2d"]
                    if box[3] - box[1] >= opts.min_person_px:
                        view = view_of(person, clip["camera"][k])
                        groups = ("all", f"action={actions[video]}", *([f"view={view}"] if view else ()))
                        judged = judge_person(judges, tally, video, rgb, person, groups)
                        people += 1
                if len(examples) < 4 and (judged is not None or len(examples) < 2):
                    examples.append({"video": video, "frame": f, "rgb": rgb, "classes": classes, "pascal_voc": voc,
                                     "cityscapes": city, "person": person, "judged": judged})  # fmt: skip
                if advance is not None:
                    advance(1)
    finally:
        reader.close()
    # Per action only where enough videos were judged (docs/realism.md): one video's figure
    # with a bootstrap of one is no interval.
    figures = {k: f for k, f in tally.figures(opts.seed).items() if "|action=" not in k or f.videos >= MIN_VIDEOS}
    if (miou := cityscapes_miou(tally, opts.seed)) is not None:
        figures["cityscapes_miou"] = miou
    for group in sorted({g for v in chosen for g in conditions[v]}):
        if (miou := cityscapes_miou(tally, opts.seed, group)) is not None:
            figures[f"cityscapes_miou|{group}"] = miou
    return RealismResult(figures, sum(len(f) for f in chosen.values()), people, len(chosen), judges.files, opts,
                         examples)  # fmt: skip


def realism_check(result: RealismResult, opts: RealismOptions) -> CheckResult:
    """Pass and report, unless a figure asked for with ``minimums`` is below its minimum."""
    report = Report()
    headline = {name: result.get(key) for name, key in HEADLINES.items()}
    for name, least in sorted(opts.minimums.items()):
        fig = headline[name]
        if fig is None:
            report.add(Finding(Reason.REALISM_BELOW_MIN, f"{name}: nothing to judge (minimum {least})",
                               numbers={"minimum": least}))  # fmt: skip
        elif fig.value < least:
            report.add(Finding(Reason.REALISM_BELOW_MIN, f"{name} {fig.value:.3f} below its minimum {least}",
                               numbers={"value": fig.value, "minimum": least}))  # fmt: skip
    said = [f"{name} {fig.said()}" for name, fig in headline.items() if fig]
    summary = (f"{result.frames} frames of {result.videos} videos, {result.people} people judged: "
               + ("; ".join(said) if said else "nothing to judge"))  # fmt: skip
    numbers = result.to_json()
    numbers["headline"] = {name: fig.to_json() for name, fig in headline.items() if fig is not None}
    return CheckResult.from_report("realism", report, summary, numbers)
