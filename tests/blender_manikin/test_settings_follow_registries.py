"""The Blender layer's obstacle shape menu and comfort weights come from the solver's registries (obstacle kinds,
standard comfort terms), checked without bpy through blender_manikin/scene/registries.py, which pose/properties.py
builds its settings from when the add-on registers. A kind and a term made up here and registered for one test
appear without a line of the Blender layer changed, and the shipped items stay as saved files hold them. The same
in a Blender session, the add-on registered again: tests/blender/test_registries.py."""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
import pytest
from test_scores_follow_registry import checkout_package


def _module(path: str):
    import importlib

    return importlib.import_module(f"{checkout_package().__name__}.{path}")


registries = _module("blender_manikin.scene.registries")
kinds, standard = _module("solver.collision.kinds"), _module("solver.comfort.standard")
ComfortTerm, Sphere = _module("solver.comfort.base").ComfortTerm, kinds.Sphere

SHIPPED_SHAPES = ["MESH", "BOX", "SPHERE", "CAPSULE", "PLANE", "CYLINDER"]  # a saved file holds each one's position


@dataclass(frozen=True, eq=False)
class Pebble(Sphere):
    """Made up for the test: a sphere under another kind's name."""

    kind = "pebble_test"
    description = "A made-up ball (test)"


class Idle(ComfortTerm):
    """Made up for the test: costs nothing."""

    name = "idle_test"
    description = "nothing at all (test)"

    def __init__(self, model) -> None:
        pass

    def cost(self, state) -> float:
        return 0.0

    def derivatives(self, state, weight: float) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros(state.n_x), np.zeros(state.n_x)


@pytest.fixture
def throwaway(monkeypatch) -> None:
    """Pebble and Idle registered for one test (what the register(...) lines of the registries do)."""
    monkeypatch.setitem(kinds.KINDS, Pebble.kind, Pebble)
    monkeypatch.setitem(standard.STANDARD_TERMS, Idle.name, standard.StandardTerm(Idle, 0.25))


def test_the_shape_menu_lists_every_kind_mesh_first() -> None:
    items = registries.shape_items()
    assert [identifier for identifier, _, _ in items] == SHIPPED_SHAPES
    assert items[0] == ("MESH", "Mesh", kinds.Mesh.description) and items[4][:2] == ("PLANE", "Plane")
    assert items[5] == ("CYLINDER", "Cylinder", kinds.Cylinder.description)
    assert all(registries.obstacle_kind(identifier).kind == identifier.lower() for identifier, _, _ in items)
    assert registries.obstacle_kind("PLANE").unbounded and not registries.obstacle_kind("BOX").unbounded


def test_the_comfort_weights_are_the_registered_terms() -> None:
    settings = registries.comfort_settings()
    assert [s.prop for s in settings] == ["comfort_range", "comfort_load", "comfort_contact",
                                          "comfort_trunk", "comfort_gaze"]  # as saved files hold; fmt: skip
    assert [(s.title, s.default) for s in settings] == [("Range", 1.0), ("Load", 1.0), ("Contact", 0.01),
                                                        ("Trunk", 5.0), ("Gaze", 0.0)]  # fmt: skip  # behaviour model
    assert settings[1].description == "Weight: joint moments / strength"
    rig = SimpleNamespace(comfort_range=2.0, comfort_load=0.5, comfort_contact=0.02, comfort_trunk=5.0,
                          comfort_gaze=0.1)  # fmt: skip
    assert registries.comfort_weights(rig) == standard.ComfortWeights(range=2.0, load=0.5, contact=0.02, trunk=5.0,
                                                                      gaze=0.1)  # fmt: skip
    registries.set_comfort_weights(rig, standard.ComfortWeights(load=3.0))
    assert vars(rig) == dict(comfort_range=1.0, comfort_load=3.0, comfort_contact=0.01, comfort_trunk=5.0,
                             comfort_gaze=0.0)  # fmt: skip


def test_a_new_kind_and_term_appear_without_a_blender_edit(throwaway) -> None:
    items = registries.shape_items()
    assert [identifier for identifier, _, _ in items] == [*SHIPPED_SHAPES, "PEBBLE_TEST"]  # the others keep their place
    assert items[-1] == ("PEBBLE_TEST", "Pebble Test", "A made-up ball (test)")
    assert registries.obstacle_kind("PEBBLE_TEST") is Pebble
    idle = registries.comfort_settings()[-1]
    assert idle == registries.ComfortSetting("comfort_idle_test", "idle_test", "Idle Test", 0.25,
                                             "Weight: nothing at all (test)")  # fmt: skip
    rig = SimpleNamespace(comfort_range=1.0, comfort_load=1.0, comfort_contact=0.01, comfort_idle_test=4.0)
    assert registries.comfort_weights(rig)["idle_test"] == 4.0
    registries.set_comfort_weights(rig, standard.ComfortWeights(idle_test=0.5))
    assert rig.comfort_idle_test == 0.5


def test_a_term_registered_after_the_settings_were_made_has_its_default(throwaway) -> None:
    """Settings made before the term was registered (no ``comfort_idle_test``): its default weight, and nothing set."""
    rig = SimpleNamespace(comfort_range=1.0, comfort_load=2.0, comfort_contact=0.01)
    assert registries.comfort_weights(rig) == standard.ComfortWeights(load=2.0, idle_test=0.25)
    registries.set_comfort_weights(rig, standard.ComfortWeights(idle_test=3.0))
    assert not hasattr(rig, "comfort_idle_test")
