"""The motion library: the built-in catalogue motions, and the clips users register.

``BUILTIN_MOTIONS`` is an immutable ``MotionLibrary`` (a read-only mapping name →
``MotionDef``) of the 128 motions of ``phav_spec.motions.MOTIONS``, each with the
catalogue's name, natural length and description and its ``catalogue.SPECS`` row as the
motion function. It is built once, when this module is imported, and nothing changes it.

Users bring their own clips (``bvh.bvh_motion``) through a separate registry:
``register_motion`` adds one, ``unregister_motion`` takes it away again. ``get_motion``
looks a name up among the registered clips first (a clip registered with ``replace=True``
stands in for a built-in of the same name), then in the library it is given, the built-ins
by default; asked for a stairs take where no flight is built, it gives the take's
``LEVEL_MOTIONS`` entry.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import replace
from types import MappingProxyType
from typing import Final, NoReturn

import numpy as np

from phav_generator.motion.animation import MotionDef
from phav_generator.motion.catalogue import SPECS
from phav_generator.motion.engine import build_motion, build_swing
from phav_spec.motions import MOTIONS


class MotionLibrary(Mapping[str, MotionDef]):
    """A read-only mapping name → ``MotionDef``: assigning or deleting entries raises."""

    __slots__ = ("_motions",)

    def __init__(self, motions: Iterable[MotionDef] = ()) -> None:
        table: dict[str, MotionDef] = {}
        for motion in motions:
            if motion.name in table:
                raise ValueError(f"motion {motion.name!r} is already registered")
            table[motion.name] = motion
        object.__setattr__(self, "_motions", MappingProxyType(table))

    def __getitem__(self, name: str) -> MotionDef:
        try:
            return self._motions[name]
        except KeyError:
            raise KeyError(f"unknown motion {name!r}") from None

    def __iter__(self) -> Iterator[str]:
        return iter(self._motions)

    def __len__(self) -> int:
        return len(self._motions)

    def __setattr__(self, name: str, value: object) -> NoReturn:
        raise AttributeError(f"a {type(self).__name__} is read-only")

    def __repr__(self) -> str:
        return f"{type(self).__name__}({len(self)} motions)"


def _catalogue_motion(name: str, *, level: bool = False) -> MotionDef:
    """The playable motion of catalogue entry ``name``: its spec row interpreted by the
    engine; ``level``: a stairs take's strides on level ground, without its climb."""
    m = MOTIONS[name]
    spec = SPECS[name]
    if level and spec.gait is not None:
        spec = replace(spec, gait=replace(spec.gait, stairs=0))
    stairs = spec.gait.stairs if spec.gait is not None else 0
    return MotionDef(name, m.length_s, build_motion(spec, m.length_s), m.description, spec.sole_friction, stairs,
                     build_swing(spec, m.length_s))  # fmt: skip


def catalogue_library() -> MotionLibrary:
    """A library of every catalogue motion, in the catalogue's order."""
    missing = [n for n in MOTIONS.names if n not in SPECS]
    if missing:
        raise RuntimeError(f"motions without an animation: {missing}")
    return MotionLibrary(_catalogue_motion(name) for name in MOTIONS.names)


#: The built-in motions: every catalogue motion, immutable.
BUILTIN_MOTIONS: Final[MotionLibrary] = catalogue_library()

#: The built-in stairs takes played on level ground, where no flight is built for them (an
#: action other than ``climb_stairs`` whose regex admits "run up stairs"): their climb
#: would lift the person into the air.
LEVEL_MOTIONS: Final[MotionLibrary] = MotionLibrary(
    _catalogue_motion(name, level=True) for name in MOTIONS.names if BUILTIN_MOTIONS[name].stairs
)

#: Users' clips (BVH imports), by name: the one registry ``register_motion`` changes.
_user_clips: dict[str, MotionDef] = {}


def register_motion(motion: MotionDef, *, replace: bool = False) -> MotionDef:
    """Register a user's clip for ``get_motion``; refuses a name already taken (a built-in
    or a registered clip) unless ``replace``."""
    if (motion.name in _user_clips or motion.name in BUILTIN_MOTIONS) and not replace:
        raise ValueError(f"motion {motion.name!r} is already registered")
    if not (np.isfinite(motion.length_s) and motion.length_s > 0):
        raise ValueError(f"motion {motion.name!r}: length must be finite and > 0")
    _user_clips[motion.name] = motion
    return motion


def unregister_motion(name: str) -> MotionDef:
    """Remove the user clip registered as ``name`` and return it (built-ins stay)."""
    try:
        return _user_clips.pop(name)
    except KeyError:
        raise KeyError(f"no registered user clip {name!r}") from None


def user_motions() -> MotionLibrary:
    """The user clips registered now, as a library (a snapshot: later registrations do not show)."""
    return MotionLibrary(_user_clips.values())


def get_motion(name: str, library: MotionLibrary = BUILTIN_MOTIONS, *, flight: bool = True) -> MotionDef:
    """The motion called ``name``: a registered user clip, else ``library``'s entry; without
    a ``flight`` of stairs under it, a built-in stairs take's level version."""
    clip = _user_clips.get(name)
    if clip is not None:
        return clip
    if not flight and library is BUILTIN_MOTIONS and name in LEVEL_MOTIONS:
        return LEVEL_MOTIONS[name]
    return library[name]
