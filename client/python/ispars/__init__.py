"""ispars: Inspection-SPARS roadmaps for robot inspection planning.

Offline, the planning library: load a Scene, grow a roadmap with a Builder, verify it, search a
tour, render a picture, save and load roadmap files. Online, a Client of isparsd daemons over
Fast DDS: load scenes, build and extend roadmaps, query stats, paths and tours, take snapshots,
and watch a roadmap grow. Arrays come out as numpy arrays without a copy per element.
docs/python.md has the quickstart in Python.
"""

from ._ispars import (  # noqa: F401
    Builder,
    Client,
    ClientError,
    InputError,
    Roadmap,
    Scene,
    SceneStatus,
    Stop,
    Watch,
    load_roadmap,
    recipe_parameters,
    render,
    tour,
)

__all__ = [
    "Builder", "Client", "ClientError", "InputError", "Roadmap", "Scene", "SceneStatus", "Stop", "Watch",
    "build", "load_roadmap", "recipe_parameters", "render", "tour",
]


def build(scene, samples, method="ispars", seed=1, variant="", threads=1, overrides=None, stop=None,
          progress=None, **parameters):
    """A Builder for the recipe, extended by `samples` samples: Builder(...) then extend(...).

    `scene` is a Scene or the path of a scene YAML file; each override by keyword (stretch=1.5)
    or in `overrides`.
    """
    if not isinstance(scene, Scene):
        scene = Scene.load(str(scene))
    builder = Builder(scene, method=method, seed=seed, variant=variant, threads=threads,
                      overrides=overrides or {}, **parameters)
    builder.extend(samples, stop=stop, progress=progress)
    return builder
