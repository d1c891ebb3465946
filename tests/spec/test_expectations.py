"""Exact expectations, cross-checked by an independent brute-force enumeration."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from phav_spec.expectations import clock_hour_cdf, duration_cdf, exact_expectations, mean_duration
from phav_spec.motions import MOTIONS
from phav_spec.theta import load_preset, parse_theta
from phav_spec.vocab import ACTIONS, CAMERAS, ENVIRONMENTS
from tests.helpers import preset_dict


def _brute_force_camera(theta) -> dict[str, float]:
    """P(C) by enumerating every (a, e, c) with plain dictionaries."""
    pa = {a: w / sum(theta.theta_a.values()) for a, w in theta.theta_a.items()}
    out = dict.fromkeys(CAMERAS.names, 0.0)
    for a, e in itertools.product(ACTIONS.names, ENVIRONMENTS.names):
        we = {x: theta.theta_e[x] * theta.theta_ae[a][x] for x in ENVIRONMENTS.names}
        if pa[a] == 0 or we[e] == 0:
            continue
        wc = {c: theta.theta_c[c] * theta.theta_ac[a][c] * theta.theta_ec[e][c] for c in CAMERAS.names}
        for c in CAMERAS.names:
            out[c] += pa[a] * we[e] / sum(we.values()) * wc[c] / sum(wc.values())
    return out


def test_camera_marginal_equals_brute_force():
    theta = load_preset()
    exact = exact_expectations(theta)["camera"].marginal_dict()
    for c, p in _brute_force_camera(theta).items():
        assert exact[c] == pytest.approx(p, abs=1e-12)
    # phav-v1 by hand: 1/35 · Σ_a P(house | a) · P(indoors | a, house). Seven actions stay
    # outdoors and climb stairs too (open sky), brush hair has three cameras in the house.
    expected_indoors = (1 / 35) * (26 * (1 / 7) * (1 / 2) + (1 / 7) * (1 / 3))
    assert exact["indoors"] == pytest.approx(expected_indoors, abs=1e-12)


def test_every_table_is_a_distribution_and_marginals_agree():
    exact = exact_expectations(load_preset())
    for name, table in exact.items():
        assert sum(table.parent_probs.values()) == pytest.approx(1.0), name
        for key, row in table.rows.items():
            assert row.sum() == pytest.approx(1.0), (name, key)
            assert (row >= 0).all()
        assert table.marginal().sum() == pytest.approx(1.0), name
    # The environment marginal through P(E | A) equals θ_E-weighted sums, action by action.
    env = exact["environment"]
    a = exact["action"].marginal()
    manual = sum(a[i] * env.rows[(name,)] for i, name in enumerate(ACTIONS.names))
    assert np.allclose(manual, env.marginal())


def test_weather_elements_are_conditioned_on_their_parent():
    exact = exact_expectations(load_preset())
    clouds = exact["clouds"]
    assert clouds.parents == ("weather", "fog")
    # fog weather: fog always on, clouds given fog: 0.5 (the paper's Bernoulli example).
    assert clouds.rows[("fog", True)][1] == pytest.approx(0.5)
    assert ("fog", False) not in clouds.rows  # fog is never off in fog weather
    # rain weather: fog on half the time; clouds on either way.
    assert clouds.rows[("rain", True)][1] == pytest.approx(1.0)
    assert clouds.parent_probs[("rain", True)] == pytest.approx(0.25 * 0.5)
    # clear: fog never, clouds otherwise 0.3; the marginal sums over the parent.
    assert clouds.rows[("clear", False)][1] == pytest.approx(0.3)
    assert clouds.marginal_dict()[True] == pytest.approx((0.3 + 1.0 + 1.0 + 0.5) / 4)
    assert exact["wet_ground"].rows[("rain", True)][1] == pytest.approx(1.0)
    assert exact["rain"].parents == ("weather",)


def test_base_motions_respect_t_min():
    data = preset_dict()
    data["durations"] = {"t_min": 3.0, "t_max": 10.0, "t_mod": 5.0}
    theta = parse_theta(data)
    rows = exact_expectations(theta)["base_motion"].rows
    for (action,), row in rows.items():
        for k, name in enumerate(MOTIONS.names):
            if row[k] > 0:
                assert MOTIONS[name].length_s >= 3.0, (action, name)


def test_continuous_cdfs():
    theta = load_preset()
    grid = np.linspace(0.0, 12.0, 241)
    f = duration_cdf(theta)(grid)
    assert f[0] == 0.0 and f[-1] == pytest.approx(1.0) and (np.diff(f) >= -1e-12).all()
    assert f[np.searchsorted(grid, 1.0)] == pytest.approx(0.0, abs=1e-12)
    # E[L] = ∫ (1 − F) on [0, 10].
    fine = np.linspace(0.0, 10.0, 20001)
    integral = np.trapezoid(1.0 - duration_cdf(theta)(fine), fine)
    assert integral == pytest.approx(mean_duration(theta), abs=1e-4)
    hours = np.linspace(0.0, 23.999, 500)
    g = clock_hour_cdf(theta)(hours)
    assert (np.diff(g) >= -1e-12).all() and g[-1] == pytest.approx(1.0, abs=1e-9)
    assert g[np.searchsorted(hours, 7.0) - 1] == pytest.approx(0.0, abs=1e-9)  # no night in phav-v1
