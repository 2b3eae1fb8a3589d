"""ispars: Inspection-SPARS roadmaps for robot inspection planning.

Offline, the planning library: load a Scene, grow a roadmap with a Builder, verify it, search a
tour, render a picture, save and load roadmap files, and bring anyone's graph in
(Roadmap.from_arrays) or take a roadmap out (to_networkx, to_scipy, save_npz, save_ply,
save_graphml). Online, a Client of isparsd daemons over Fast DDS: load scenes, build and extend
roadmaps, query stats, paths and tours, take snapshots, and watch a roadmap grow. Arrays come out
as numpy arrays without a copy per element. docs/python.md has the quickstart in Python.
"""

try:
    import numpy as _numpy  # noqa: F401  (the module's arrays are numpy arrays)
except ImportError as _error:
    raise ImportError(
        "ispars needs numpy, which this python3 does not have. With Debian's python3: "
        "apt-get install python3-numpy; in a venv: make it with python3 -m venv --system-site-packages "
        "(Debian's numpy), or pip install numpy") from _error

from . import graphs as _graphs
from ._ispars import (  # noqa: F401
    HAS_CLIENT,
    Builder,
    ClientError,
    InputError,
    Roadmap,
    Scene,
    Stop,
    load_roadmap,
    path,
    recipe_parameters,
    render,
    tour,
)
from ._version import __version__  # noqa: F401

if HAS_CLIENT:
    from ._ispars import Client, SceneStatus, Watch  # noqa: F401

load_npz = _graphs.load_npz
Roadmap.to_networkx = _graphs.to_networkx
Roadmap.to_scipy = _graphs.to_scipy
Roadmap.save_npz = _graphs.save_npz

__all__ = [
    "Builder", "Client", "ClientError", "HAS_CLIENT", "InputError", "Roadmap", "Scene", "SceneStatus", "Stop",
    "Watch", "__version__", "build", "load_npz", "load_roadmap", "path", "recipe_parameters", "render", "tour",
]
if not HAS_CLIENT:
    __all__ = [name for name in __all__ if name not in ("Client", "SceneStatus", "Watch")]

_CLIENT_NAMES = ("Client", "SceneStatus", "Watch")


def __getattr__(name):
    if name in _CLIENT_NAMES:
        raise AttributeError(
            f"ispars.{name} is not in this install: it was built without the DDS client (Fast DDS was not found). "
            "Install libfastrtps-dev and reinstall with: pip install --no-build-isolation . --config-settings client=on")
    raise AttributeError(f"module 'ispars' has no attribute {name!r}")


def build(scene, samples, method="ispars", seed=1, variant="", threads=1, overrides=None, stop=None,
          progress=None, memory_mb=0, **parameters):
    """A Builder for the recipe, extended by `samples` samples: Builder(...) then extend(...).

    `scene` is a Scene or the path of a scene YAML file (str or os.PathLike); each override by
    keyword (stretch=1.5) or in `overrides`; `memory_mb` as Builder's (0: half of this machine's
    memory).
    """
    builder = Builder(scene, method=method, seed=seed, variant=variant, threads=threads,
                      overrides=overrides or {}, memory_mb=memory_mb, **parameters)
    builder.extend(samples, stop=stop, progress=progress)
    return builder
