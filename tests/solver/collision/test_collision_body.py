"""The body's collision capsules: one per link with mass, sized from the manikin's own segment masses and lengths,
standing on the floor with the feet touching it, and carried by their links."""

from __future__ import annotations

import numpy as np
import pytest

from solver.collision.body import DENSITY, MAX_RADIUS, MIN_RADIUS, body_capsules
from solver.io.scenario.bodies import list_presets, load_body


@pytest.mark.parametrize("preset", list_presets())
def test_one_capsule_per_link_with_mass_and_none_below_the_floor(preset: str) -> None:
    model = load_body(preset=preset)
    capsules = body_capsules(model)
    heavy = {model.link_names[j] for j in np.flatnonzero(model.mass > 0)}
    assert set(capsules.names) == heavy and len(capsules) == len(heavy)
    assert np.all((capsules.radius >= MIN_RADIUS) & (capsules.radius <= MAX_RADIUS))
    p0, p1 = capsules.world(model.forward(model.zero_pose()))
    lowest = np.minimum(p0[:, 2], p1[:, 2]) - capsules.radius
    assert np.all(np.isfinite(p0)) and np.all(np.isfinite(p1))
    assert lowest.min() >= -1e-9  # standing: nothing sinks into the floor
    soles = {model.link_names[t.link] for t in model.tcps.values() if t.sole is not None}
    on_floor = {n for n, z in zip(capsules.names, lowest, strict=True) if z < 1e-9}
    assert {n for n in soles if n in heavy} <= on_floor  # the feet (the snake's base) touch it


def test_a_limb_holds_its_mass_at_the_density_of_water() -> None:
    model = load_body(preset="male_50")
    capsules = body_capsules(model)
    for name in ("upper_arm_r", "forearm_l", "thigh_r", "shank_l", "head"):
        i = capsules.names.index(name)
        length = np.linalg.norm(capsules.end[i] - capsules.start[i])
        mass = model.mass[model.link_names.index(name)]
        assert np.pi * capsules.radius[i] ** 2 * length * DENSITY == pytest.approx(mass, rel=1e-9)


def test_bigger_manikins_get_thicker_limbs() -> None:
    small, big = body_capsules(load_body(preset="female_5")), body_capsules(load_body(preset="male_95"))
    for name in ("thigh_r", "upper_arm_l", "shank_r"):
        assert big.radius[big.names.index(name)] > small.radius[small.names.index(name)]


def test_capsules_ride_on_their_links() -> None:
    model = load_body(preset="male_50")
    capsules = body_capsules(model)
    theta = model.zero_pose() + np.random.default_rng(5).uniform(-0.4, 0.4, model.n)
    kin = model.forward(theta)
    p0, p1 = capsules.world(kin)
    rot, pos = kin.rotation[capsules.link], kin.position[capsules.link]
    back0 = np.einsum("kji,kj->ki", rot, p0 - pos)
    back1 = np.einsum("kji,kj->ki", rot, p1 - pos)
    np.testing.assert_allclose(back0, capsules.start, atol=1e-12)
    np.testing.assert_allclose(back1, capsules.end, atol=1e-12)
