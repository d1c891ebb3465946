"""The simulation's output: world poses per frame and physics signals, saveable and comparable.

A ``Trajectory`` covers the clip's frames plus one beyond it (every frame has forward
flow). Arrays only, no MuJoCo objects, so the renderer and the validators read it without
MuJoCo; ``save``/``load`` use one ``.npz`` written atomically, with the MuJoCo state of
every frame so a video can be re-rendered or a re-simulation compared without re-running.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from phav_spec.errors import PhavUserError
from phav_spec.files import atomic_write

TRAJECTORY_FORMAT_VERSION = 1


@dataclass(frozen=True)
class PersonTrack:
    """One person over the frames: body poses, the animation targets and control state."""

    person_id: int
    role: str
    body_pos: np.ndarray  # (F, 15, 3) world body origins
    body_quat: np.ndarray  # (F, 15, 4)
    target_pos: np.ndarray  # (F, 15, 3) body origins of the animation it follows
    q: np.ndarray  # (F, 30) joint angles
    strengths: np.ndarray  # (F, 15) servo strength per muscle
    pin: np.ndarray  # (F,) root pin weight
    lower: np.ndarray  # (30,) joint limits, radians
    upper: np.ndarray
    height_m: float
    penetration_m: np.ndarray  # (F,) deepest world penetration of this person (NaN: kinematic, not measured)
    limit_excess_rad: np.ndarray  # (F,) largest joint-limit violation of this person


@dataclass(frozen=True)
class PropTrack:
    name: str
    object: str
    pixel_class: str
    shape: str
    size: tuple[float, ...]
    pos: np.ndarray  # (F, 3)
    quat: np.ndarray  # (F, 4)


@dataclass(frozen=True)
class Trajectory:
    """World poses of people, props and camera per frame, and the physics signals."""

    video_id: str
    fps: int
    timestep: float
    times: np.ndarray  # (F,) seconds; F = n_frames + 1
    people: tuple[PersonTrack, ...]
    props: tuple[PropTrack, ...]
    cam_to_world: np.ndarray  # (F, 4, 4): OpenGL camera (looks down −Z, +Y up)
    intrinsics: tuple[float, float, float, float]  # fx, fy, cx, cy in pixels
    boxes: tuple[tuple[str, tuple[float, float, float], tuple[float, float, float], float], ...]
    manipulations: tuple[tuple[str, int, str, str, float, float], ...]
    penetration_m: np.ndarray  # (F,) deepest person–world penetration
    camera_penetration_m: np.ndarray  # (F,) deepest camera–world penetration
    limit_excess_rad: np.ndarray  # (F,) largest joint-limit violation over all simulated people
    kinetic_energy_j: np.ndarray  # (F,)
    warnings: dict[str, int]
    exploded_at: int | None  # first frame not simulated (held at the last good state), or None
    contacts: dict[str, np.ndarray] = field(default_factory=dict)  # (F,) bool per named contact
    mj_state: np.ndarray | None = None  # (F, nstate) MuJoCo full physics state per frame
    #: (F,) smallest ground-plane distance from any person's body (or the car-hit car) to any
    #: traffic vehicle (1000 m when there is no traffic); vehicles yield, so it stays positive.
    traffic_clearance_m: np.ndarray | None = None

    @property
    def n_frames(self) -> int:
        """Frames of the clip (the trajectory holds one more)."""
        return len(self.times) - 1

    def arrays(self) -> dict[str, np.ndarray]:
        """Every array, flattened to names (for hashing, saving and comparing)."""
        out: dict[str, np.ndarray] = {
            "times": self.times,
            "cam_to_world": self.cam_to_world,
            "penetration_m": self.penetration_m,
            "camera_penetration_m": self.camera_penetration_m,
            "limit_excess_rad": self.limit_excess_rad,
            "kinetic_energy_j": self.kinetic_energy_j,
        }
        for p in self.people:
            for f in fields(PersonTrack):
                v = getattr(p, f.name)
                if isinstance(v, np.ndarray):
                    out[f"person{p.person_id}.{f.name}"] = v
        for prop in self.props:
            out[f"prop.{prop.name}.pos"] = prop.pos
            out[f"prop.{prop.name}.quat"] = prop.quat
        for name, v in self.contacts.items():
            out[f"contact.{name}"] = v
        if self.mj_state is not None:
            out["mj_state"] = self.mj_state
        if self.traffic_clearance_m is not None:
            out["traffic_clearance_m"] = self.traffic_clearance_m
        return out

    def content_hash(self) -> str:
        """sha256 over every array's name, dtype, shape and bytes (state included)."""
        h = hashlib.sha256()
        for name, v in sorted(self.arrays().items()):
            a = np.ascontiguousarray(v)
            h.update(name.encode())
            h.update(str(a.dtype).encode())
            h.update(str(a.shape).encode())
            h.update(a.tobytes())
        return h.hexdigest()

    def person(self, person_id: int) -> PersonTrack:
        for p in self.people:
            if p.person_id == person_id:
                return p
        raise KeyError(f"no person {person_id} in {self.video_id}")

    def save(self, path: str | Path) -> None:
        """Write one ``.npz`` atomically: arrays plus a JSON header for everything else."""
        header = {
            "format_version": TRAJECTORY_FORMAT_VERSION,
            "video_id": self.video_id,
            "fps": self.fps,
            "timestep": self.timestep,
            "intrinsics": list(self.intrinsics),
            "boxes": [list(b) for b in self.boxes],
            "manipulations": [list(m) for m in self.manipulations],
            "warnings": self.warnings,
            "exploded_at": self.exploded_at,
            "people": [{"person_id": p.person_id, "role": p.role, "height_m": p.height_m} for p in self.people],
            "props": [
                {
                    "name": p.name,
                    "object": p.object,
                    "pixel_class": p.pixel_class,
                    "shape": p.shape,
                    "size": list(p.size),
                }
                for p in self.props
            ],
            "contacts": sorted(self.contacts),
        }
        arrays = self.arrays()
        arrays["header"] = np.frombuffer(json.dumps(header, sort_keys=True).encode(), dtype=np.uint8)
        with atomic_write(path) as tmp, open(tmp, "wb") as fh:
            np.savez(fh, **arrays)

    @classmethod
    def load(cls, path: str | Path) -> Trajectory:
        """Read a trajectory written by ``save``; a damaged or foreign file is a user error."""
        try:
            with np.load(path, allow_pickle=False) as z:
                data = {k: z[k] for k in z.files}
            header = json.loads(bytes(data.pop("header")).decode())
        except (OSError, ValueError, KeyError) as exc:
            raise PhavUserError(f"not a readable trajectory file ({exc})", source=str(path)) from None
        version = header.get("format_version")
        if version != TRAJECTORY_FORMAT_VERSION:
            raise PhavUserError(
                f"format version {version!r} is not supported (expected {TRAJECTORY_FORMAT_VERSION})",
                source=str(path),
                field="format_version",
            )
        people = tuple(
            PersonTrack(
                person_id=p["person_id"],
                role=p["role"],
                height_m=p["height_m"],
                **{
                    f.name: data[f"person{p['person_id']}.{f.name}"]
                    for f in fields(PersonTrack)
                    if f"person{p['person_id']}.{f.name}" in data
                },
            )
            for p in header["people"]
        )
        props = tuple(
            PropTrack(
                name=p["name"],
                object=p["object"],
                pixel_class=p["pixel_class"],
                shape=p["shape"],
                size=tuple(p["size"]),
                pos=data[f"prop.{p['name']}.pos"],
                quat=data[f"prop.{p['name']}.quat"],
            )
            for p in header["props"]
        )
        return cls(
            video_id=header["video_id"],
            fps=header["fps"],
            timestep=header["timestep"],
            times=data["times"],
            people=people,
            props=props,
            cam_to_world=data["cam_to_world"],
            intrinsics=tuple(header["intrinsics"]),
            boxes=tuple((b[0], tuple(b[1]), tuple(b[2]), b[3]) for b in header["boxes"]),
            manipulations=tuple(tuple(m) for m in header["manipulations"]),
            penetration_m=data["penetration_m"],
            camera_penetration_m=data["camera_penetration_m"],
            limit_excess_rad=data["limit_excess_rad"],
            kinetic_energy_j=data["kinetic_energy_j"],
            warnings=header["warnings"],
            exploded_at=header["exploded_at"],
            contacts={name: data[f"contact.{name}"] for name in header["contacts"]},
            mj_state=data.get("mj_state"),
            traffic_clearance_m=data.get("traffic_clearance_m"),
        )


def compare(a: Trajectory, b: Trajectory) -> dict[str, float]:
    """Largest absolute difference per array between two trajectories of the same recipe."""
    xa, xb = a.arrays(), b.arrays()
    if set(xa) != set(xb):
        missing = sorted(set(xa) ^ set(xb))
        raise ValueError(f"trajectories hold different arrays: {missing}")
    out = {}
    for name in sorted(xa):
        if xa[name].shape != xb[name].shape:
            raise ValueError(f"{name}: shapes differ {xa[name].shape} vs {xb[name].shape}")
        out[name] = float(np.max(np.abs(xa[name].astype(np.float64) - xb[name].astype(np.float64)), initial=0.0))
    return out
