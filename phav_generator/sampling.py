"""θ → recipes by ancestral sampling of the paper's graphical model.

The factorisation is the paper's P1(D, W) P2(H) P3(A, L, B, V, C, E, …) (Section "Model").
Video i's recipe depends only on (θ, dataset seed, i): each part of the model draws from its
own stream of video i (``phav_spec.seeding``), so sampling 10 or 40,000 videos gives the same
recipe i and adding a draw to one part never moves the draws of another.
Every draw is one ``rng.random()`` double turned into a value by phav_spec.distributions;
a part's draw order is part of the dataset's definition (changing it bumps the recipe
schema version).

People are the paper's H (a human model per person from θ_H) or, with θ's ``people.mode:
sampled``, drawn continuously: each person from its own stream ``person/<person id>``, a
fixed number of draws per person, so a person's look depends only on (θ, seed, video,
person id) and on whether the action allows a child.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np

from phav_spec.distributions import (
    Categorical,
    sample_integer,
    sample_subset,
    triangular_inverse_cdf,
)
from phav_spec.motions import MOTIONS, active_start, meeting_start
from phav_spec.people import BOTTOMS, FABRICS, HAIR_STYLES, TOPS, Phenotype
from phav_spec.population import (
    HAIR_COLOURS,
    estimated_stature,
    hair_rgb,
    hsv_rgb,
    p_grey,
    phenotype_for,
    reference_stature,
    skin_rgb,
)
from phav_spec.recipe import SAMPLED_PERSON, Recipe, frames_for, video_id
from phav_spec.scene import (
    ACTION_SCENES,
    CAMERA_INFO,
    ENVIRONMENT_SCENES,
    HUMAN_MODELS,
    SPRING_MIN_DISTANCES_M,
    WEATHER_ELEMENTS,
    EnvironmentScene,
    Vec3,
)
from phav_spec.seeding import PartStreams, named_seed, runtime_seeds
from phav_spec.theta import SEXES, PeopleTheta, Theta
from phav_spec.vocab import (
    ACTIONS,
    CAMERAS,
    DAY_PHASES,
    ENVIRONMENTS,
    MUSCLES,
    VARIATIONS,
    WEATHERS,
)

#: The named parts of the model, each with its own random stream (and, with sampled
#: people, one stream per person: ``person_stream(person_id)``).
PARTS: tuple[str, ...] = (
    "world", "human", "action", "environment", "background", "variation", "camera", "supporting",
)  # fmt: skip
#: Variables ``RecipeSampler.sample(force=…)`` and ``phav vary --set`` can fix.
VARIABLES: tuple[str, ...] = (
    "weather", "day_phase", "clock_hour", "rain", "fog", "clouds", "wet_ground", "sun_brightness",
    "ambient_luminosity", "cloud_intensity", "fog_intensity", "rain_intensity", "camera",
)  # fmt: skip


def _rotate(dx: float, dy: float, heading_deg: float) -> tuple[float, float]:
    h = math.radians(heading_deg)
    return dx * math.cos(h) - dy * math.sin(h), dx * math.sin(h) + dy * math.cos(h)


def _human(name: str) -> dict:
    return HUMAN_MODELS[name].human(name)


def person_stream(person_id: int) -> str:
    """The name of a sampled person's random stream."""
    return f"person/{person_id}"


def _stature(human: Mapping[str, Any]) -> float:
    """Standing height (m) of a recipe person (``HumanSpec`` data), from its phenotype."""
    return estimated_stature(Phenotype(**human["phenotype"]))


class PeopleSampler:
    """Draws people from θ's ``people`` section (categoricals compiled once).

    One person is a fixed sequence of uniform doubles from its stream: sex, child, age,
    stature z, gender offset, weight, muscle, proportions, skin tone and undertone, hair
    style, grey, hair colour, shade, then top (kind, fabric, two HSV colours, pattern
    scale), bottom (the same) and shoes (HSV).
    """

    def __init__(self, spec: PeopleTheta):
        self.spec = spec
        self._styles = {sex: Categorical(list(spec.hair.styles[sex].values())) for sex in _supported(spec)}
        self._bottoms = {sex: Categorical(list(spec.outfit.bottoms[sex].values())) for sex in _supported(spec)}
        self._colours = Categorical(list(spec.hair.colours.values()))
        self._tops = Categorical(list(spec.outfit.tops.values()))
        self._top_fabrics = Categorical(list(spec.outfit.top_fabrics.values()))
        self._bottom_fabrics = Categorical(list(spec.outfit.bottom_fabrics.values()))

    def _hsv(self, rng: np.random.Generator, saturation: Any, value: Any) -> dict[str, float]:
        hue = math.fmod(360.0 * rng.random(), 360.0)
        return {"hue_deg": hue, "saturation": saturation.sample(rng=rng), "value": value.sample(rng=rng)}

    def _garment(
        self, rng: np.random.Generator, kinds: tuple[str, ...], kind: Categorical, fabric: Categorical
    ) -> tuple[dict, list[dict]]:
        """A garment's kind, fabric, ground and pattern colours and pattern scale."""
        o = self.spec.outfit
        k, f = kinds[kind.sample(rng=rng)], FABRICS[fabric.sample(rng=rng)]
        ground, pattern = self._hsv(rng, o.saturation, o.value), self._hsv(rng, o.saturation, o.value)
        garment = {
            "kind": k, "fabric": f, "rgb": hsv_rgb(**ground), "pattern_rgb": hsv_rgb(**pattern),
            "scale": o.pattern_scale.sample(rng=rng),
        }  # fmt: skip
        return garment, [ground, pattern]

    def sample(self, rng: np.random.Generator, *, child_allowed: bool) -> dict[str, Any]:
        """One person as ``HumanSpec`` data (model ``sampled``, with its draws)."""
        spec = self.spec
        female = rng.random() < spec.p_female
        child = rng.random() < spec.p_child and child_allowed
        age = (spec.child_age_years if child else spec.adult_age_years).sample(rng=rng)
        z = spec.stature_z.sample(rng=rng)
        offset = spec.gender_offset.sample(rng=rng)
        weight, muscle, proportions = (spec.weight.sample(rng=rng), spec.muscle.sample(rng=rng),
                                       spec.proportions.sample(rng=rng))  # fmt: skip
        tone, undertone = spec.skin_tone.sample(rng=rng), spec.skin_undertone.sample(rng=rng)
        sex = "female" if female else "male"
        style = HAIR_STYLES[self._styles[sex].sample(rng=rng)]
        g = spec.hair.grey
        grey = rng.random() < p_grey(age, start_years=g.start_years, full_years=g.full_years, p_full=g.p_full)
        colour = HAIR_COLOURS[self._colours.sample(rng=rng)]
        colour = "grey" if grey else colour
        shade = rng.random()
        top, top_colours = self._garment(rng, TOPS, self._tops, self._top_fabrics)
        bottom, bottom_colours = self._garment(rng, BOTTOMS, self._bottoms[sex], self._bottom_fabrics)
        shoes = self._hsv(rng, spec.outfit.shoes_saturation, spec.outfit.shoes_value)
        median, sd = reference_stature(female, age)
        stature = median + z * sd
        phenotype = phenotype_for(female=female, age=age, stature_m=stature, gender_offset=offset, muscle=muscle,
                                  weight=weight, proportions=proportions)  # fmt: skip
        return {
            "model": SAMPLED_PERSON,
            "phenotype": phenotype.model_dump(),
            "skin_rgb": skin_rgb(tone, undertone),
            "hair": {"style": style, "rgb": hair_rgb(colour, shade)},
            "outfit": {"top": top, "bottom": bottom, "shoes_rgb": hsv_rgb(**shoes)},
            "sampled": {
                "female": female,
                "adult_age_years": None if child else age,
                "child_age_years": age if child else None,
                "stature_z": z,
                "stature_m": stature,
                "gender_offset": offset,
                "skin_tone": tone,
                "skin_undertone": undertone,
                "hair_colour": colour,
                "hair_shade": shade,
                "garment_colours": [*top_colours, *bottom_colours],
                "shoes_colour": shoes,
            },
        }


def _supported(spec: PeopleTheta) -> list[str]:
    """The sexes θ draws (P > 0)."""
    return [sex for sex in SEXES.names if spec.p_sex()[sex] > 0]


class RecipeSampler:
    """Samples recipes from one θ; tables are compiled once, recipes drawn on demand."""

    def __init__(self, theta: Theta):
        self.theta = theta
        arr = theta.arrays
        self._a = Categorical(arr.a)
        self._w = Categorical(arr.w)
        self._d = Categorical(arr.d)
        self._people = PeopleSampler(theta.people) if theta.people is not None else None
        if self._people is None:
            self._h = Categorical(arr.h)
            self._h_without = [
                Categorical(np.where(np.arange(len(arr.h)) == i, 0.0, arr.h)) if np.count_nonzero(arr.h) > 1 else None
                for i in range(len(arr.h))
            ]
        pe, pv, pb, pc = (
            arr.p_e_given_a(),
            arr.p_v_given_a(),
            arr.p_b_given_a(),
            self._camera_weights(),
        )
        reach = arr.a > 0
        self._e = [Categorical(pe[i]) if reach[i] else None for i in range(len(ACTIONS))]
        self._v = [Categorical(pv[i]) if reach[i] else None for i in range(len(ACTIONS))]
        self._b = [Categorical(pb[i]) if reach[i] else None for i in range(len(ACTIONS))]
        self._c = [
            [Categorical(pc[i, j]) if reach[i] and pe[i, j] > 0 else None for j in range(len(ENVIRONMENTS))]
            for i in range(len(ACTIONS))
        ]
        # (a, b, c) on the real line; a wrapped night interval runs past 24 h.
        self._clock = [theta.clock_hours[d].distribution().unwrapped() for d in DAY_PHASES.names]
        self._dead_zone = {
            name: Categorical(np.array(cam.springs.dead_zone_weights()))
            for name, cam in theta.cameras.items()
            if cam.springs is not None
        }
        self._lengths = [MOTIONS[m].length_s for m in MOTIONS.names]
        self._streams = PartStreams(PARTS)

    def _camera_weights(self) -> np.ndarray:
        """Unnormalised P(C | A, E) ∝ θ_C·θ_AC·θ_EC (the hook a planted-bug test replaces)."""
        return self.theta.arrays.p_c_given_ae()

    def sample(self, dataset_seed: int, index: int, *, force: Mapping[str, Any] | None = None) -> Recipe:
        """The recipe of video ``index`` of the dataset with seed ``dataset_seed``.

        ``force`` fixes variables (``VARIABLES``) of a counterfactual recipe: every draw still
        happens, in the same order, and a forced variable replaces the drawn value, so what
        depends on it (clock time on the day phase, weather elements on the weather, a
        camera's parameters on its kind) follows the same uniforms and nothing else moves.
        """
        force = dict(force or {})
        unknown = sorted(set(force) - set(VARIABLES))
        if unknown:
            raise ValueError(f"cannot force {unknown}; variables: {', '.join(VARIABLES)}")
        self._streams.start(dataset_seed, index)
        theta = self.theta

        world = self._world(force)
        # P2(H): the protagonist's human model, or a person drawn once the action is known.
        h = self._h.sample(rng=self._streams["human"]) if self._people is None else -1
        a, b, duration, motion = self._motion()
        action = ACTIONS.names[a]
        protagonist = self._person(0, action) if h < 0 else _human(HUMAN_MODELS.names[h])
        e, wp, position, heading = self._place(a)
        env_name = ENVIRONMENTS.names[e]
        env = ENVIRONMENT_SCENES[env_name]

        background = self._background(env, first_id=ACTIONS[action].n_people)
        variation = self._variation(a, b, duration * motion["speed"])
        camera = self._camera(a, e, position, heading, _stature(protagonist), force.get("camera"))
        supporting = self._supporting(action, h, position, heading)
        if supporting and supporting[0]["placement"] == "facing":
            # Two people walking into each other on a take that stops them: the clip starts
            # where they meet as it does (wherever θ would start it, they mostly stopped apart).
            meet = meeting_start(motion["base_motion"], motion["base_motion_length_s"], duration * motion["speed"],
                                 supporting[0]["distance_m"])  # fmt: skip
            if meet is not None:
                motion = {**motion, "start_s": meet}

        return Recipe.model_validate(
            {
                "video_id": video_id(index),
                "index": index,
                "dataset_seed": dataset_seed,
                "theta_hash": theta.hash,
                "action": action,
                "n_people": ACTIONS[action].n_people,
                "duration_s": duration,
                "n_frames": frames_for(duration, theta.video.fps),
                "video": theta.video.model_dump(),
                "motion": motion,
                "variation": variation,
                "protagonist": {
                    "human": protagonist,
                    "position": position,
                    "heading_deg": heading,
                },
                "supporting_characters": supporting,
                "environment": {
                    "name": env_name,
                    "indoor": env.indoor,
                    "waypoint_index": wp,
                    "waypoint": position,
                    "look_seed": named_seed(self._streams.key, "look") if theta.world_variety == "video" else None,
                },
                "background_actors": background,
                "camera": camera,
                "world": world,
                "render": theta.render,
                "seeds": runtime_seeds(self._streams.key),
            }
        )

    def _person(self, person_id: int, action: str | None) -> dict[str, Any]:
        """A sampled person from its own stream; a child only where ``action`` allows one
        (``None``: a background pedestrian, who always may be)."""
        allowed = action is None or ACTION_SCENES[action].children
        return self._people.sample(self._streams[person_stream(person_id)], child_allowed=allowed)  # type: ignore[union-attr]

    def _world(self, force: Mapping[str, Any]) -> dict[str, Any]:
        """P1(D, W): day phase, clock time given the phase, weather and its elements."""
        theta = self.theta
        rng = self._streams["world"]
        d = self._d.sample(rng=rng)
        d = DAY_PHASES.index(force["day_phase"]) if "day_phase" in force else d
        clock_hour = math.fmod(triangular_inverse_cdf(*self._clock[d], rng.random()), 24.0)
        w = self._w.sample(rng=rng)
        w = WEATHERS.index(force["weather"]) if "weather" in force else w
        wt = theta.weather_elements[WEATHERS.names[w]]
        on: dict[str, bool] = {}
        for element, info in WEATHER_ELEMENTS.items():
            parent_on = on[info.parent] if info.parent is not None else None
            on[element] = rng.random() < wt.p_on(element, parent_on)
            on[element] = bool(force.get(element, on[element]))
        world = {
            "day_phase": DAY_PHASES.names[d],
            "clock_hour": clock_hour,
            "weather": WEATHERS.names[w],
            "sun_brightness": wt.sun_brightness.sample(rng=rng),
            "ambient_luminosity": wt.ambient_luminosity.sample(rng=rng),
            **on,
        }
        # Intensities are always drawn (fixed draw count), and zero when the element is off.
        for element, key in (
            ("clouds", "cloud_intensity"),
            ("fog", "fog_intensity"),
            ("rain", "rain_intensity"),
        ):
            value = getattr(wt, key).sample(rng=rng)
            world[key] = value if on[element] else 0.0
        for key in ("clock_hour", "sun_brightness", "ambient_luminosity", "cloud_intensity", "fog_intensity",
                    "rain_intensity"):  # fmt: skip
            if key in force:
                world[key] = float(force[key])
        return world

    def _motion(self) -> tuple[int, int, float, dict[str, Any]]:
        """P3: the action, its base motion and clip length, and playback parameters
        (action index, motion index, duration in seconds, the recipe's ``motion``)."""
        theta = self.theta
        rng = self._streams["action"]
        a = self._a.sample(rng=rng)
        b = self._b[a].sample(rng=rng)
        length_b = self._lengths[b]
        duration = triangular_inverse_cdf(*theta.durations.clip_length(length_b), rng.random())
        speed = theta.motion.speed.sample(rng=rng)
        mirror = rng.random() < theta.motion.p_mirror
        u = rng.random()
        if theta.motion.start == "active":
            start_s = active_start(MOTIONS.names[b], length_b, duration * speed, u)
        else:
            start_s = u * max(0.0, length_b - duration * speed)
        motion = {
            "base_motion": MOTIONS.names[b],
            "base_motion_length_s": length_b,
            "start_s": start_s,
            "speed": speed,
            "mirror": mirror,
        }
        return a, b, duration, motion

    def _place(self, a: int) -> tuple[int, int, Vec3, float]:
        """Environment E | A, the protagonist's waypoint P_W and heading (environment index,
        waypoint index, position, heading in degrees)."""
        rng = self._streams["environment"]
        e = self._e[a].sample(rng=rng)
        env = ENVIRONMENT_SCENES[ENVIRONMENTS.names[e]]
        wp = sample_integer(0, len(env.protagonist_waypoints) - 1, rng=rng)
        position = env.protagonist_waypoints[wp]
        heading = self.theta.protagonist_heading_deg.sample(rng=rng)
        return e, wp, position, heading

    def _background(self, env: EnvironmentScene, first_id: int) -> list[dict]:
        """Background pedestrians on the environment's B_WG graph (none indoors)."""
        graph = env.background_waypoints
        if not graph:
            return []
        rng = self._streams["background"]
        spec = self.theta.background_actors
        n = sample_integer(spec.count.min, spec.count.max, rng=rng)
        actors = []
        for k in range(n):
            human = (
                self._person(first_id + k, None)
                if self._people
                else _human(HUMAN_MODELS.names[self._h.sample(rng=rng)])
            )
            start = sample_integer(0, len(graph) - 1, rng=rng)
            dest = sample_integer(0, len(graph) - 2, rng=rng)
            dest += dest >= start  # any waypoint but the start
            actors.append({
                "person_id": first_id + k,
                "human": human,
                "start_waypoint": start,
                "destination_waypoint": dest,
                "start": graph[start],
                "destination": graph[dest],
                "speed_mps": spec.speed_mps.sample(rng=rng),
            })  # fmt: skip
        return actors

    def _variation(self, a: int, b: int, played_s: float) -> dict:
        """V | A and its parameters Θ_v (Section "Action variations"); ``played_s``: how much of
        a motion the clip plays (its duration × speed), the blended motion's too."""
        rng = self._streams["variation"]
        kind = VARIATIONS.names[self._v[a].sample(rng=rng)]
        scene = ACTION_SCENES[ACTIONS.names[a]]
        params = self.theta.variations
        if kind == "random_perturbation":
            spec = params.random_perturbation
            k = _subset_size(spec.n_muscles.min, spec.n_muscles.max, len(scene.complementary_muscles), rng=rng)
            return {
                "kind": kind,
                "muscles": sample_subset(scene.complementary_muscles, k, rng=rng),
                "radius_m": spec.radius_m.sample(rng=rng),
                "period_s": spec.period_s.sample(rng=rng),
            }
        if kind == "muscle_weakening":
            spec = params.muscle_weakening
            k = _subset_size(spec.n_muscles.min, spec.n_muscles.max, len(MUSCLES), rng=rng)
            muscles = sample_subset(MUSCLES.names, k, rng=rng)
            return {
                "kind": kind,
                "muscles": muscles,
                "strengths": tuple(spec.strength.sample(rng=rng) for _ in muscles),
            }
        if kind == "action_blending":
            spec = params.action_blending
            k = _subset_size(spec.n_muscles.min, spec.n_muscles.max, len(scene.complementary_muscles), rng=rng)
            muscles = sample_subset(scene.complementary_muscles, k, rng=rng)
            other = sample_integer(0, len(MOTIONS) - 2, rng=rng)
            other += other >= b  # a different motion sequence, from any action
            other_len = self._lengths[other]
            return {
                "kind": kind,
                "muscles": muscles,
                "blend_motion": MOTIONS.names[other],
                "blend_start_s": rng.random() * max(0.0, other_len - played_s),
                "weight": spec.weight.sample(rng=rng),
            }
        if kind == "objects":
            options = scene.variation_objects
            return {"kind": kind, "object": options[sample_integer(0, len(options) - 1, rng=rng)]}
        return {"kind": "none"}

    def _camera(
        self,
        a: int,
        e: int,
        position: Vec3,
        heading: float,
        stature_m: float,
        forced_kind: str | None = None,
    ) -> dict:
        """C | A, E, its placement C_xyz / T_xyz around P_xyz and its parameters Θ_c."""
        rng = self._streams["camera"]
        kind = CAMERAS.names[self._c[a][e].sample(rng=rng)]
        kind = forced_kind if forced_kind is not None else kind
        spec = self.theta.cameras[kind]
        fov = spec.fov_deg.sample(rng=rng)
        distance = spec.distance_m.sample(rng=rng)
        height = spec.height_m.sample(rng=rng)
        azimuth = spec.azimuth_deg.sample(rng=rng)
        dx, dy = _rotate(distance, 0.0, heading + azimuth)
        x, y, z = position
        # The target starts on the standing protagonist's anchor (physics.plan.camera): the
        # pelvis, or for the close-up two thirds of the way from the chest's origin to the neck.
        target_height = 0.77 * stature_m if kind == "closeup" else 0.53 * stature_m
        springs = impulse = None
        if CAMERA_INFO[kind].tracking == "springs":
            s = spec.springs
            springs = {
                "ct_spring_strength": s.ct_spring_strength.sample(rng=rng),
                "tp_spring_strength": s.tp_spring_strength.sample(rng=rng),
                "camera_mass": s.camera_mass.sample(rng=rng),
                "target_mass": s.target_mass.sample(rng=rng),
                "camera_drag": s.camera_drag.sample(rng=rng),
                "target_drag": s.target_drag.sample(rng=rng),
                "ct_min_distance_m": SPRING_MIN_DISTANCES_M[self._dead_zone[kind].sample(rng=rng)],
                "tp_min_distance_m": SPRING_MIN_DISTANCES_M[self._dead_zone[kind].sample(rng=rng)],
            }
            impulse = {
                "strength": spec.impulse.strength.sample(rng=rng),
                "azimuth_deg": spec.impulse.azimuth_deg.sample(rng=rng),
                "elevation_deg": spec.impulse.elevation_deg.sample(rng=rng),
            }
        return {
            "kind": kind,
            "fov_deg": fov,
            "distance_m": distance,
            "height_m": height,
            "azimuth_deg": azimuth,
            "position": (x + dx, y + dy, z + height),
            "target": (x, y, z + target_height),
            "springs": springs,
            "impulse": impulse,
        }

    def _supporting(self, action: str, h: int, position: Vec3, heading: float) -> list[dict]:
        """Supporting characters: a human model from H without the protagonist's (or a person
        drawn from θ's people), placed by S_xyz."""
        placement = ACTION_SCENES[action].supporting_placement
        if placement is None:
            return []
        rng = self._streams["supporting"]
        human = _human(HUMAN_MODELS.names[self._h_without[h].sample(rng=rng)]) if h >= 0 else self._person(1, action)
        spec = self.theta.supporting_characters
        if placement == "side_by_side":
            distance = spec.side_distance_m.sample(rng=rng)
            dx, dy, turn = 0.0, -distance, 0.0  # to the protagonist's right
        elif placement == "behind":
            distance = spec.behind_distance_m.sample(rng=rng)
            dx, dy, turn = -distance, 0.0, 0.0
        else:
            distance = spec.facing_distance_m.sample(rng=rng)
            dx, dy, turn = distance, 0.0, 180.0
        rx, ry = _rotate(dx, dy, heading)
        x, y, z = position
        return [{
            "person_id": 1,
            "human": human,
            "placement": placement,
            "distance_m": distance,
            "position": (x + rx, y + ry, z),
            "heading_deg": math.fmod(heading + turn, 360.0),
        }]  # fmt: skip


def _subset_size(lo: int, hi: int, available: int, *, rng: np.random.Generator) -> int:
    """Uniform size in [lo, hi] capped by how many muscles are available (at least one)."""
    hi = min(hi, available)
    lo = max(1, min(lo, hi))
    return sample_integer(lo, hi, rng=rng)


def sample_recipes(theta: Theta, *, n: int, seed: int, start: int = 0) -> Iterator[Recipe]:
    """Recipes ``start`` … ``start + n - 1`` of the dataset (θ, seed)."""
    sampler = RecipeSampler(theta)
    for i in range(start, start + n):
        yield sampler.sample(seed, i)
