# Type stubs of the ispars package (the extension module ispars._ispars and build()).
import os
from typing import Any, Callable, Iterator, Optional, TypedDict

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
U32 = npt.NDArray[np.uint32]
PathLike = str | os.PathLike[str]

__version__: str
HAS_CLIENT: bool  # built with the DDS client (Client, SceneStatus, Watch)

class InputError(ValueError):
    """Bad input; str() is 'FILE: FIELD: PROBLEM' as the CLI prints it."""
    file: str
    field: str
    problem: str

class ClientError(RuntimeError):
    """A failed call to isparsd."""
    kind: str  # 'no_daemon', 'timeout', 'rejected', 'protocol' or 'forbidden'

class Stop:
    """A stop any thread may set; the long calls given it end within half a second."""
    def __init__(self) -> None: ...
    def set(self) -> None: ...
    def clear(self) -> None: ...
    @property
    def is_set(self) -> bool: ...

class Scene:
    """A scene: the structure's mesh, its POIs, the sampling box and the roadmap parameters."""
    @staticmethod
    def load(path: PathLike) -> Scene: ...
    @property
    def name(self) -> str: ...
    @property
    def root(self) -> F64: ...  # (3,)
    @property
    def pois(self) -> F64: ...  # (P, 3), read-only view
    @property
    def bounds(self) -> F64: ...  # (2, 3)
    @property
    def mesh(self) -> tuple[npt.NDArray[np.float32], U32]: ...  # (V, 3) corners, (F, 3) triangles
    @property
    def robot_radius(self) -> float: ...
    @property
    def sensor_range(self) -> float: ...
    @property
    def dense_delta(self) -> float: ...
    @property
    def sparse_delta(self) -> float: ...
    @property
    def stretch(self) -> float: ...
    @property
    def fingerprint(self) -> str: ...
    def point_valid(self, point: npt.ArrayLike) -> bool: ...
    def segment_valid(self, a: npt.ArrayLike, b: npt.ArrayLike) -> bool: ...

class Roadmap:
    """A roadmap; immutable, its arrays read-only views into it."""
    @staticmethod
    def from_arrays(positions: npt.ArrayLike, edges: npt.ArrayLike, costs: Optional[npt.ArrayLike] = None,
                    visibility: Optional[tuple[npt.ArrayLike, npt.ArrayLike] | list[Any]] = None,
                    poi_count: Optional[int] = None) -> Roadmap: ...
    @property
    def vertex_count(self) -> int: ...
    @property
    def edge_count(self) -> int: ...
    @property
    def component_count(self) -> int: ...
    @property
    def poi_count(self) -> int: ...
    @property
    def version(self) -> int: ...
    @property
    def digest(self) -> int: ...
    @property
    def covered_pois(self) -> int: ...
    @property
    def covered_pois_root(self) -> int: ...
    @property
    def positions(self) -> F64: ...  # (V, 3), read-only view
    @property
    def edges(self) -> U32: ...  # (E, 2), read-only view
    @property
    def costs(self) -> F64: ...  # (E,)
    def visibility(self) -> tuple[npt.NDArray[np.int64], U32]: ...
    def pois_of(self, vertex: int) -> U32: ...
    def components(self) -> U32: ...
    def neighbors(self, vertex: int) -> U32: ...
    def save(self, path: PathLike, scene: str, root: npt.ArrayLike, pois: npt.ArrayLike,
             dense: Optional[Roadmap] = None) -> None: ...
    def to_networkx(self) -> Any: ...  # networkx.Graph
    def to_scipy(self) -> Any: ...  # scipy.sparse.csr_matrix, (V, V)
    def save_npz(self, path: PathLike) -> None: ...
    def save_ply(self, path: PathLike) -> None: ...
    def save_graphml(self, path: PathLike) -> None: ...

class Builder:
    """A roadmap under construction from a recipe; the same recipe gives the same roadmap."""
    def __init__(self, scene: Scene | PathLike, method: str = "ispars", seed: int = 1, variant: str = "",
                 threads: int = 1, overrides: dict[str, float | int] = ..., memory_mb: int = 0,
                 **parameters: float | int) -> None: ...
    def extend(self, samples: int, stop: Optional[Stop] = None,
               progress: Optional[Callable[[int, int, int, int], Any]] = None) -> int: ...
    def expected_cost(self, samples: int) -> dict[str, float]: ...
    @property
    def roadmap(self) -> Roadmap: ...
    @property
    def dense(self) -> Optional[Roadmap]: ...
    @property
    def dense_ids(self) -> U32: ...
    @property
    def samples(self) -> int: ...
    @property
    def scene(self) -> Scene: ...
    @property
    def recipe(self) -> dict[str, Any]: ...
    def verify(self, stop: Optional[Stop] = None) -> dict[str, Any]: ...

class Tour(TypedDict, total=False):
    """The one tour model of tour() and Client.tour() (docs/python.md, 'Tours')."""
    cost: float  # the walk's length on the graph
    walk: U32  # vertex ids, closed at vertex 0
    waypoints: F64  # (n, 3): the walk's positions
    covered: int  # targets the walk sees
    target_count: int
    lower_bound: Optional[float]  # proven; None when none was
    bound_complete: bool
    trace: F64  # (n, 2): seconds, cost
    bound_trace: F64  # (n, 2): seconds, bound
    valid: bool
    problem: str
    seconds: float
    version: int  # the roadmap version searched
    flown: bool  # the flown keys below are None when False
    shortcut_path: Optional[F64]
    shortcut_cost: Optional[float]
    flown_path: Optional[F64]  # (n, 3): stops, closed at the root
    flown_sees: Optional[list[U32]]  # per stop: target POI ids it sees
    flown_cost: Optional[float]
    stages: list[dict[str, Any]]  # stage, cost, seconds
    graph_vertices: Optional[int]
    graph_edges: Optional[int]
    # tour() only: the search's details.
    targets: U32
    covered_ids: U32
    bound_note: str
    iterations: int
    candidates: int
    # Client.tour() only: the reply's.
    server_id: str
    message: str
    status: SceneStatus

def build(scene: Scene | PathLike, samples: int, method: str = "ispars", seed: int = 1, variant: str = "",
          threads: int = 1, overrides: Optional[dict[str, float | int]] = None, stop: Optional[Stop] = None,
          progress: Optional[Callable[[int, int, int, int], Any]] = None, memory_mb: int = 0,
          **parameters: float | int) -> Builder: ...
def recipe_parameters() -> list[dict[str, Any]]: ...
def tour(roadmap: Roadmap, budget: Optional[float] = None, iterations: int = 0, seed: int = 1, threads: int = 1,
         targets: Optional[npt.ArrayLike] = None, bound: bool = True, stop: Optional[Stop] = None,
         progress: Optional[Callable[[float, float, Optional[float]], Any]] = None, scene: Optional[Scene] = None,
         samples: int = 0) -> Tour: ...
def render(scene: Scene, roadmap: Optional[Roadmap] = None, dense: Optional[Roadmap] = None,
           tour: Optional[npt.ArrayLike] = None, width: int = 800, height: int = 600,
           path: PathLike = "") -> npt.NDArray[np.uint8]: ...
def load_roadmap(path: PathLike, graph: str = "roadmap") -> Roadmap: ...
def load_npz(path: PathLike) -> Roadmap: ...

class SceneStatus:
    """A scene's status as its owning daemon published it."""
    state: str
    scene: str
    server_id: str
    method: str
    variant: str
    seed: int
    generation: int
    samples_done: int
    samples_target: int
    accepted_generation: int
    version: int
    vertices: int
    edges: int
    components: int
    dense_vertices: int
    dense_edges: int
    poi_count: int
    pois_covered: int
    pois_covered_root: int
    dense_delta: float
    sparse_delta: float
    stretch: float
    p_accept: float
    last_error: str
    scene_fingerprint: str
    tasks: int

class Batch(TypedDict):
    generation: int
    version: int
    vertex_count: int
    edge_count: int
    samples_done: int
    resynced: bool
    first_vertex: int
    positions: F64  # (new vertices, 3)
    first_edge: int
    edges: U32  # (new edges, 2)

class Watch:
    """A live replica of a scene's roadmap; iterate for batches of what is new."""
    def __iter__(self) -> Iterator[Batch]: ...
    def __next__(self) -> Batch: ...
    def next(self, timeout: Optional[float] = None) -> Optional[Batch]: ...
    def roadmap(self) -> Roadmap: ...
    def close(self) -> None: ...
    def __enter__(self) -> Watch: ...
    def __exit__(self, *args: Any) -> None: ...

class Client:
    """A connection to every isparsd on a DDS domain."""
    def __init__(self, domain: Optional[int] = None, profile_file: str = "", profile_name: str = "ispars",
                 security: str = "", timeout: float = 15.0, server: str = "") -> None: ...
    @property
    def id(self) -> str: ...
    @property
    def closed(self) -> bool: ...
    def close(self) -> None: ...
    def __enter__(self) -> Client: ...
    def __exit__(self, *args: Any) -> None: ...
    def scenes(self) -> list[dict[str, Any]]: ...
    def load(self, scene: str) -> dict[str, Any]: ...
    def unload(self, scene: str) -> dict[str, Any]: ...
    def build(self, scene: str, samples: int, method: str = "ispars", seed: int = 1, variant: str = "",
              overrides: dict[str, float | int] = ..., replace: bool = False,
              **parameters: float | int) -> dict[str, Any]: ...
    def extend(self, scene: str, samples: int) -> dict[str, Any]: ...
    def cancel(self, scene: str) -> dict[str, Any]: ...
    def drop(self, scene: str) -> dict[str, Any]: ...
    def stats(self, scene: str) -> SceneStatus: ...
    def path(self, scene: str, start: npt.ArrayLike, goal: npt.ArrayLike) -> dict[str, Any]: ...
    def verify(self, scene: str) -> dict[str, Any]: ...
    def snapshot(self, scene: str) -> dict[str, Any]: ...
    def tour(self, scene: str, budget: float = 5.0, seed: int = 1, targets: npt.ArrayLike = ..., task: str = "",
             progress: Optional[Callable[[float, float, Optional[float]], Any]] = None) -> Tour: ...
    def wait_idle(self, scene: str, timeout: float = 600.0,
                  progress: Optional[Callable[[SceneStatus], Any]] = None) -> SceneStatus: ...
    def watch(self, scene: str) -> Watch: ...
    def add_task(self, scene: str, name: str, pois: Optional[npt.ArrayLike] = None, sample: int = 0,
                 seed: int = 1) -> dict[str, Any]: ...
    def tasks(self, scene: str) -> list[dict[str, Any]]: ...
    def remove_task(self, scene: str, name: str) -> dict[str, Any]: ...
