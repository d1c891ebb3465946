"""Action probe: can the 35 actions be told apart from the simulated motion alone?

The features see only the physics output of the people (no recipe, no labels): the
protagonist's joint angles and body positions relative to the pelvis in the pelvis's
heading frame, divided by body height, summarised over time so a clip's phase does not matter; the pelvis's
speed, height, turning and falls; and where another person is near, the distance to them
and between hands. A multinomial logistic regression trained on some seeds and tested on
others then says how many actions the motions, physics rules included, make recognisable.
Everything is numpy and deterministic: fixed iterations, no random initialisation.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from phav_generator.motion.rotations import quat_to_matrix
from phav_generator.motion.skeleton import BONE_INDEX
from phav_generator.physics.simulate import simulate
from phav_generator.physics.trajectory import PersonTrack, Trajectory
from phav_generator.sampling import sample_recipes
from phav_spec.theta import Theta, parse_theta

#: Feature value standing for "nobody else near" (in body heights).
FAR = 5.0
_HANDS = [BONE_INDEX["left_hand"], BONE_INDEX["right_hand"]]
_FEET = [BONE_INDEX["left_foot"], BONE_INDEX["right_foot"]]


def _heading_frames(track: PersonTrack) -> np.ndarray:
    """(F, 3, 3) rotations to the pelvis's heading frame: yaw only, +X forward, +Z up."""
    rot = quat_to_matrix(track.body_quat[:, BONE_INDEX["pelvis"]])
    yaw = np.arctan2(rot[:, 1, 0], rot[:, 0, 0])
    c, s = np.cos(yaw), np.sin(yaw)
    out = np.zeros((len(yaw), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 1, 0], out[:, 1, 1], out[:, 2, 2] = c, s, -s, c, 1.0
    return out


def _summary(x: np.ndarray) -> np.ndarray:
    """Mean, standard deviation, minimum and maximum over the first (time) axis, flattened."""
    return np.concatenate([x.mean(0).ravel(), x.std(0).ravel(), x.min(0).ravel(), x.max(0).ravel()])


def motion_features(tr: Trajectory) -> np.ndarray:
    """One feature vector per clip from the protagonist's (and others') simulated bodies."""
    p = tr.people[0]
    h = p.height_m
    dt = 1.0 / tr.fps
    pos = p.body_pos
    pelvis = pos[:, BONE_INDEX["pelvis"]]
    heading = _heading_frames(p)
    local = np.einsum("fij,fbj->fbi", heading, pos - pelvis[:, None]) / h
    local = np.delete(local, BONE_INDEX["pelvis"], axis=1)
    local_vel = np.abs(np.diff(local, axis=0)) / dt
    ground = pos[0, _FEET, 2].min()
    height = (pos[:, :, 2] - ground) / h
    vel = np.diff(pelvis, axis=0) / dt / h
    planar = np.einsum("fij,fj->fi", heading[:-1], vel)
    yaw_rate = np.abs(np.diff(np.unwrap(np.arctan2(heading[:, 0, 1], heading[:, 0, 0]))) / dt)
    up = quat_to_matrix(p.body_quat[:, BONE_INDEX["chest"]])[:, 2, 2]  # chest's z axis · world up
    parts = [
        _summary(local),
        local_vel.mean(0).ravel(),
        _summary(p.q),
        np.abs(np.diff(p.q, axis=0)).mean(0) / dt,
        _summary(planar),
        _summary(height[:, [BONE_INDEX["pelvis"], BONE_INDEX["head"], *_HANDS, *_FEET]]),
        _summary(np.stack([yaw_rate, up[1:]], axis=1)),
        _others(tr, p),
    ]
    return np.concatenate(parts)


def _others(tr: Trajectory, p: PersonTrack) -> np.ndarray:
    """Distances (in heights) to the nearest other non-background person: pelvis and hands."""
    others = [o for o in tr.people[1:] if o.role != "background"]
    if not others:
        return np.full(4, FAR)
    pelvis = p.body_pos[:, BONE_INDEX["pelvis"]]
    near = min(others, key=lambda o: float(np.linalg.norm(o.body_pos[:, 0] - pelvis, axis=-1).mean()))
    d = np.linalg.norm(near.body_pos[:, 0] - pelvis, axis=-1) / p.height_m
    hands = np.linalg.norm(p.body_pos[:, _HANDS, None] - near.body_pos[:, None, _HANDS], axis=-1)
    dh = hands.reshape(len(d), -1).min(axis=1) / p.height_m
    return np.minimum(np.array([d.mean(), d.min(), dh.mean(), dh.min()]), FAR)


@dataclass(frozen=True)
class LogisticProbe:
    """Multinomial logistic regression on standardised features (L2, full-batch gradient)."""

    classes: tuple[str, ...]
    mean: np.ndarray
    scale: np.ndarray
    weights: np.ndarray  # (D + 1, C), last row the bias

    @classmethod
    def fit(
        cls, x: np.ndarray, labels: list[str], *, l2: float = 1e-3, iterations: int = 2000, rate: float = 0.5
    ) -> LogisticProbe:
        """Fit by gradient descent from zero weights: deterministic for the same data."""
        classes = tuple(sorted(set(labels)))
        y = np.array([classes.index(c) for c in labels])
        mean = x.mean(0)
        scale = x.std(0)
        scale[scale < 1e-9] = 1.0
        z = _with_bias((x - mean) / scale)
        onehot = np.eye(len(classes))[y]
        w = np.zeros((z.shape[1], len(classes)))
        for _ in range(iterations):
            prob = _softmax(z @ w)
            grad = z.T @ (prob - onehot) / len(z)
            grad[:-1] += l2 * w[:-1]
            w -= rate * grad
        return cls(classes, mean, scale, w)

    def predict(self, x: np.ndarray) -> list[str]:
        """The most probable class of each row."""
        z = _with_bias((x - self.mean) / self.scale)
        return [self.classes[i] for i in np.argmax(z @ self.weights, axis=1)]


def _with_bias(z: np.ndarray) -> np.ndarray:
    return np.concatenate([z, np.ones((len(z), 1))], axis=1)


def _softmax(a: np.ndarray) -> np.ndarray:
    e = np.exp(a - a.max(axis=1, keepdims=True))
    return e / e.sum(axis=1, keepdims=True)


def confusion_matrix(truth: list[str], predicted: list[str], classes: tuple[str, ...]) -> np.ndarray:
    """Counts (C, C): row = true class, column = predicted class, in ``classes`` order."""
    index = {c: i for i, c in enumerate(classes)}
    out = np.zeros((len(classes), len(classes)), dtype=np.int64)
    for t, p in zip(truth, predicted, strict=True):
        out[index[t], index[p]] += 1
    return out


def format_confusion(matrix: np.ndarray, classes: tuple[str, ...]) -> str:
    """A plain-text confusion matrix with per-class recall, for logs and docs."""
    width = max(len(c) for c in classes)
    head = " " * (width + 1) + " ".join(f"{i:>2d}" for i in range(len(classes))) + "  recall"
    lines = [head]
    for i, c in enumerate(classes):
        row = matrix[i]
        recall = row[i] / max(row.sum(), 1)
        cells = " ".join(f"{v:>2d}" if v else " ." for v in row)
        lines.append(f"{c:<{width}} {cells}  {recall:5.0%}  ({i})")
    return "\n".join(lines)


def single_action_theta(theta: Theta, action: str, seconds: float) -> Theta:
    """``theta`` making only ``action``, with every clip ``seconds`` long (all else unchanged)."""
    data = theta.model_dump(mode="json")
    data["theta_a"] = {a: (1.0 if a == action else 0.0) for a in data["theta_a"]}
    data["durations"] = {"t_min": seconds, "t_max": seconds, "t_mod": seconds}
    return parse_theta(data, source=f"<{theta.name} restricted to {action}>")


@dataclass(frozen=True)
class ProbeResult:
    """Held-out accuracy of the action probe, its confusion matrix and what it cost."""

    classes: tuple[str, ...]
    confusion: np.ndarray  # (C, C) test counts, row = true action
    n_train: int
    n_test: int
    simulate_s: float  # wall time simulating every clip
    fit_s: float

    @property
    def accuracy(self) -> float:
        return float(np.trace(self.confusion) / max(self.confusion.sum(), 1))


def evaluate_probe(
    theta: Theta,
    actions: tuple[str, ...],
    *,
    n_train: int,
    n_test: int,
    seed: int = 0,
    seconds: float = 2.0,
    progress: Callable[[int], None] | None = None,
) -> ProbeResult:
    """Simulate ``n_train`` clips per action from seed ``seed`` and ``n_test`` from ``seed + 1``,
    fit the probe on the first and report its confusion on the second."""
    split: dict[str, tuple[list[np.ndarray], list[str]]] = {"train": ([], []), "test": ([], [])}
    start = time.perf_counter()
    for action in actions:
        restricted = single_action_theta(theta, action, seconds)
        for name, s, n in (("train", seed, n_train), ("test", seed + 1, n_test)):
            for recipe in sample_recipes(restricted, n=n, seed=s):
                split[name][0].append(motion_features(simulate(recipe, keep_state=False)))
                split[name][1].append(action)
                if progress is not None:
                    progress(1)
    simulated = time.perf_counter() - start
    probe = LogisticProbe.fit(np.stack(split["train"][0]), split["train"][1])
    predicted = probe.predict(np.stack(split["test"][0]))
    fitted = time.perf_counter() - start - simulated
    classes = tuple(actions)
    confusion = confusion_matrix(split["test"][1], predicted, classes)
    return ProbeResult(classes, confusion, n_train, n_test, simulated, fitted)
