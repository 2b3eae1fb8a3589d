"""One tour model: ispars.tour's dict has the keys and types Client.tour's has (test_client.py
checks the daemon's against MODEL too), one progress signature, and iterations that end a call."""
import time

import numpy as np
import pytest

from conftest import SCENES

SCENE = SCENES / "truss_bridge.yaml"

# The model's keys and their types, offline and online (None: the flown keys without a scene).
MODEL = {
    "cost": float, "walk": np.ndarray, "waypoints": np.ndarray, "covered": int, "target_count": int,
    "lower_bound": (float, type(None)), "bound_complete": bool, "trace": np.ndarray, "bound_trace": np.ndarray,
    "valid": bool, "problem": str, "seconds": float, "version": int, "flown": bool,
    "shortcut_path": (np.ndarray, type(None)), "shortcut_cost": (float, type(None)),
    "flown_path": (np.ndarray, type(None)), "flown_sees": (list, type(None)), "flown_cost": (float, type(None)),
    "stages": list, "graph_vertices": (int, type(None)), "graph_edges": (int, type(None)),
}
OFFLINE_EXTRAS = {"targets", "covered_ids", "bound_note", "iterations", "candidates"}


def check_model(tour, extras):
    assert set(tour) == set(MODEL) | extras, set(tour) ^ (set(MODEL) | extras)
    for key, kind in MODEL.items():
        assert isinstance(tour[key], kind), (key, type(tour[key]))
    assert tour["walk"][0] == 0 and tour["walk"][-1] == 0
    assert tour["waypoints"].shape == (len(tour["walk"]), 3)


@pytest.fixture(scope="module")
def built(ispars):
    return ispars.build(ispars.Scene.load(SCENE), 4000, method="ispars", seed=1)


def test_the_offline_tour_is_the_model_with_and_without_a_scene(ispars, built):
    plain = ispars.tour(built.roadmap, budget=1, iterations=40)
    check_model(plain, OFFLINE_EXTRAS)
    assert plain["flown"] is False and plain["flown_path"] is None and plain["stages"] == []
    assert plain["covered"] == len(plain["covered_ids"]) == plain["target_count"] == len(plain["targets"])
    assert np.array_equal(plain["waypoints"], built.roadmap.positions[plain["walk"]])
    assert plain["version"] == built.roadmap.version
    flown = ispars.tour(built.roadmap, budget=5, iterations=40, scene=built.scene, samples=4000)
    check_model(flown, OFFLINE_EXTRAS)
    assert flown["flown"] is True and flown["flown_cost"] <= flown["shortcut_cost"] <= flown["cost"]


def test_progress_starts_with_a_tour_and_bound_is_none_until_proven(ispars, built):
    seen = []
    result = ispars.tour(built.roadmap, budget=2, progress=lambda t, cost, bound: seen.append((t, cost, bound)))
    assert seen, "no progress"
    assert all(isinstance(cost, float) and cost > 0 for _, cost, _ in seen)
    bounds = [b for _, _, b in seen]
    assert all(b is None or isinstance(b, float) for b in bounds)
    assert seen[-1][1] == pytest.approx(result["cost"]) or seen[-1][2] is not None
    none = ispars.tour(built.roadmap, budget=1, bound=False, progress=lambda t, c, b: seen.append(b))
    assert none["bound_trace"].shape == (0, 2)


def test_iterations_alone_end_the_call_when_they_end(ispars, built):
    started = time.monotonic()
    tour = ispars.tour(built.roadmap, iterations=50)
    took = time.monotonic() - started
    assert tour["valid"] and tour["iterations"] >= 50
    assert took < 5.0, f"iterations=50 took {took:.1f} s: the default 10 s budget ran on"
    again = ispars.tour(built.roadmap, iterations=50)
    assert again["cost"] == tour["cost"], "iterations alone are deterministic"


@pytest.mark.parametrize("kwargs, field", [
    (dict(budget=0), "budget"), (dict(budget=3601), "budget"), (dict(budget=float("nan")), "budget"),
    (dict(budget="5"), "budget"), (dict(iterations=-1), "iterations"), (dict(iterations=2.5), "iterations"),
    (dict(threads=0), "threads"), (dict(seed=-1), "seed"), (dict(seed=2**64), "seed"),
    (dict(targets=[1.5]), "targets"), (dict(targets=[-3]), "targets"), (dict(samples=-1), "samples"),
])
def test_bad_tour_arguments_are_input_errors(ispars, built, kwargs, field):
    with pytest.raises(ispars.InputError) as e:
        ispars.tour(built.roadmap, **kwargs)
    assert (e.value.file, e.value.field) == ("tour", field), str(e.value)
