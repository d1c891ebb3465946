"""How segmenters trained on real photographs name our pixel classes (the realism check).

Each of our pixel classes is either *judged as* one of the judge's classes — the class its
annotators were told to name it by — or *not judged*, with the reason: PASCAL VOC's
annotation guidelines leave lorries and trucks out of `car` and benches out of `chair`, so
a model trained on them is right to call either background, and neither is judged by it
(Cityscapes judges trucks; no judge has a bench class); Cityscapes labels guard rails as a
class of their own that its models are not trained on. A figure is always reported under
our class: a tree judged as vegetation stays a tree, never pooled into vegetation. Where a
judge splits what the paper's class table keeps as one class, its finer answers count as
the class they belong to (*merged*: Cityscapes' sidewalk is the paper's road, which has no
pavement class of its own). The judges' label lists are in their output ids' order.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

from phav_spec.vocab import PIXEL_CLASSES, PixelGroup


@dataclass(frozen=True)
class JudgeClasses:
    """A segmenter's label list and what each of our pixel classes is judged as."""

    judge: str
    #: The judge's class names by output id.
    labels: tuple[str, ...]
    #: Our class → the judge's class it should be labelled as.
    judged_as: Mapping[str, str]
    #: Our class → why the judge does not judge it.
    not_judged: Mapping[str, str]
    #: A judge class finer than ours → the judge class its answers count as.
    merged: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))
    #: Whether pixels of the classes it does not judge are void (in no figure), as its own
    #: benchmark leaves out what it has no class for (Cityscapes' ``ignoreInEval``); VOC's
    #: annotations call everything outside its classes background, where an answer counts.
    void_unjudged: bool = False

    def label_id(self, name: str) -> int:
        return self.labels.index(name)

    def answer_ids(self, name: str) -> tuple[int, ...]:
        """The judge's output ids that answer ``name``: its own and those merged into it."""
        return (self.label_id(name), *(self.label_id(k) for k, v in sorted(self.merged.items()) if v == name))


def _people(name: str) -> dict[str, str]:
    groups = (PixelGroup.HUMAN_PARTS, PixelGroup.HUMAN_JOINTS)
    return {c: name for c, info in PIXEL_CLASSES.items() if info.group in groups}


def _rest(judged: Mapping[str, str], named: Mapping[str, str], reason: str) -> dict[str, str]:
    """Every class neither judged nor given its own reason, with ``reason``."""
    return {c: named.get(c, reason) for c, _ in PIXEL_CLASSES.items() if c not in judged}


_VOC_LABELS = (
    "background", "aeroplane", "bicycle", "bird", "boat", "bottle", "bus", "car", "cat", "chair", "cow",
    "diningtable", "dog", "horse", "motorbike", "person", "pottedplant", "sheep", "sofa", "train", "tvmonitor",
)  # fmt: skip

_VOC_JUDGED = {
    "car": "car", "bus": "bus",
    "chair": "chair", "sofa": "sofa", "table": "diningtable", "screen": "tvmonitor",
    **_people("person"),
}  # fmt: skip

#: DeepLabV3-MobileNetV2 on PASCAL VOC 2012: the objects people touch and pass.
PASCAL_VOC = JudgeClasses(
    judge="pascal_voc",
    labels=_VOC_LABELS,
    judged_as=MappingProxyType(_VOC_JUDGED),
    not_judged=MappingProxyType(
        _rest(
            _VOC_JUDGED,
            {
                "unlabeled": "void",
                "misc": "mixed objects (cups, bottles, boxes, carts, bars)",
                "truck": "VOC's car leaves out lorries and trucks (its annotation guidelines)",
                "bench": "VOC's chair leaves out benches (its annotation guidelines)",
                "vegetation": "no VOC class (pottedplant is a plant in a pot)",
                "tree": "no VOC class (pottedplant is a plant in a pot)",
            },
            "no VOC class: the scene around the objects",
        )
    ),
)

_CITYSCAPES_LABELS = (
    "road", "sidewalk", "building", "wall", "fence", "pole", "traffic light", "traffic sign", "vegetation",
    "terrain", "sky", "person", "rider", "car", "truck", "bus", "train", "motorcycle", "bicycle",
)  # fmt: skip

_CITYSCAPES_JUDGED = {
    "road": "road", "building": "building", "pole": "pole", "traffic_light": "traffic light",
    "traffic_sign": "traffic sign", "vegetation": "vegetation", "tree": "vegetation", "terrain": "terrain",
    "sky": "sky", "car": "car", "truck": "truck", "bus": "bus",
    **_people("person"),
}  # fmt: skip

#: DeepLab (MobileNet-EdgeTPU slim) on Cityscapes: street scenes, outdoor environments only.
CITYSCAPES = JudgeClasses(
    judge="cityscapes",
    labels=_CITYSCAPES_LABELS,
    judged_as=MappingProxyType(_CITYSCAPES_JUDGED),
    not_judged=MappingProxyType(
        _rest(
            _CITYSCAPES_JUDGED,
            {
                "unlabeled": "void",
                "misc": "mixed objects (cups, bottles, boxes, carts, bars)",
                "bench": "no Cityscapes class",
                "stairs": "no one Cityscapes class: outdoor steps, and the stadium's stands (void, as bench)",
                "guard_rail": "Cityscapes labels guard rails as their own class, left out of training (trainId 255)",
            },
            "no Cityscapes class (an indoor class or a prop)",
        )
    ),
    # Our road is the paper's: carriageways and the pavements beside them.
    merged=MappingProxyType({"sidewalk": "road"}),
    void_unjudged=True,
)

#: The segmenters' class tables by judge name.
JUDGE_CLASSES: Mapping[str, JudgeClasses] = MappingProxyType({j.judge: j for j in (PASCAL_VOC, CITYSCAPES)})
