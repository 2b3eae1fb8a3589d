"""A roadmap in other tools' formats: networkx, scipy.sparse and .npz (PLY and GraphML are written in
C++: Roadmap.save_ply, Roadmap.save_graphml, as `ispars snapshot --out` writes them).

Each export takes a Roadmap and writes or returns the same graph: vertex v at positions[v]
seeing the POIs visibility() gives it, edge k between edges[k] with weight costs[k] (its length).
Files are written whole or not at all (a temporary file renamed into place). networkx and scipy
are imported when first needed: `apt-get install python3-networkx python3-scipy`, or in a venv
`pip install ispars[graphs]`.
"""

import os
import tempfile
import zipfile

import numpy as np

# The npz format's name and version, checked on reading: another file is refused by name.
_NPZ_FORMAT = "ispars-roadmap"
_NPZ_VERSION = 1


def _input_error(file, field, problem):
    """An ispars.InputError as the library raises them: 'FILE: FIELD: PROBLEM' with the parts."""
    from ._ispars import InputError

    error = InputError(f"{file}: {field}: {problem}")
    error.file, error.field, error.problem = file, field, problem
    return error


def _needs(module, package):
    try:
        return __import__(module, fromlist=["_"])
    except ImportError as e:
        raise ImportError(f"this export needs {module}: apt-get install python3-{package} (Debian's python3), "
                          f"or pip install {package} in a venv") from e


def _write_atomically(path, write):
    """Calls write(file object) on a temporary file beside `path`, then renames it into place."""
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    handle, temporary = tempfile.mkstemp(prefix=".ispars-", dir=directory)
    try:
        with os.fdopen(handle, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise


def _poi_lists(roadmap):
    offsets, ids = roadmap.visibility()
    return [ids[offsets[v]:offsets[v + 1]] for v in range(roadmap.vertex_count)]


def to_networkx(roadmap):
    """An undirected networkx.Graph: node v has `pos` (x, y, z) and `pois` (a list of POI ids);
    each edge has `weight`, its length. Node ids are the roadmap's vertex ids."""
    nx = _needs("networkx", "networkx")
    graph = nx.Graph(poi_count=roadmap.poi_count)
    positions = roadmap.positions
    for v, pois in enumerate(_poi_lists(roadmap)):
        graph.add_node(v, pos=tuple(float(c) for c in positions[v]), pois=[int(p) for p in pois])
    graph.add_weighted_edges_from(
        (int(u), int(v), float(c)) for (u, v), c in zip(roadmap.edges, roadmap.costs))
    return graph


def to_scipy(roadmap):
    """The (V, V) symmetric adjacency as a scipy.sparse.csr_matrix of edge lengths, ready for
    scipy.sparse.csgraph (shortest_path, connected_components, minimum_spanning_tree)."""
    sparse = _needs("scipy.sparse", "scipy")
    edges = np.asarray(roadmap.edges, dtype=np.int64).reshape(-1, 2)
    costs = roadmap.costs
    rows = np.concatenate([edges[:, 0], edges[:, 1]])
    cols = np.concatenate([edges[:, 1], edges[:, 0]])
    n = roadmap.vertex_count
    return sparse.csr_matrix((np.concatenate([costs, costs]), (rows, cols)), shape=(n, n))


def save_npz(roadmap, path):
    """Writes the roadmap as a compressed .npz of its arrays, change-log order included: load_npz
    gives back a roadmap with the same digest."""
    positions, edges, (offsets, ids), poi_count, edges_before = roadmap.__getstate__()
    arrays = dict(format=np.array(_NPZ_FORMAT), format_version=np.array(_NPZ_VERSION), positions=positions,
                  edges=edges, costs=roadmap.costs, visibility_offsets=offsets, visibility_ids=ids,
                  poi_count=np.array(poi_count), edges_before=edges_before, digest=np.array(roadmap.digest, np.uint64))
    _write_atomically(path, lambda f: np.savez_compressed(f, **arrays))


def load_npz(path):
    """A roadmap from save_npz's file, checked as Roadmap.from_arrays checks its arrays; raises
    InputError (file: the path) when the file is not one or its digest does not match."""
    from ._ispars import InputError, Roadmap

    name = os.fspath(path)
    try:
        with np.load(name, allow_pickle=False) as f:
            if "format" not in f or str(f["format"]) != _NPZ_FORMAT:
                raise _input_error(name, "format", "not an ispars roadmap .npz (Roadmap.save_npz writes one)")
            if int(f["format_version"]) != _NPZ_VERSION:
                raise _input_error(name, "format_version", f"{int(f['format_version'])} is not {_NPZ_VERSION}")
            state = (f["positions"], f["edges"], (f["visibility_offsets"], f["visibility_ids"]),
                     int(f["poi_count"]), f["edges_before"])
            digest = int(f["digest"])
    except (OSError, ValueError, KeyError, zipfile.BadZipFile) as e:
        if isinstance(e, InputError):
            raise
        raise _input_error(name, "file", f"cannot be read as an ispars roadmap .npz ({e})") from e
    roadmap = Roadmap.__new__(Roadmap)
    roadmap.__setstate__(state)
    if roadmap.digest != digest:
        raise _input_error(name, "digest", f"the arrays give {roadmap.digest:#x}, the file says {digest:#x} (damaged)")
    return roadmap
