"""A roadmap in other tools' formats: networkx, scipy.sparse, .npz, PLY and GraphML.

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


def save_ply(roadmap, path):
    """Writes an ASCII PLY (MeshLab, CloudCompare, Open3D, Blender): a `vertex` element with x, y,
    z and the number of POIs each sees, and an `edge` element with vertex1 and vertex2."""
    positions = roadmap.positions
    seen = np.diff(roadmap.visibility()[0])
    edges = roadmap.edges

    def write(f):
        f.write((f"ply\nformat ascii 1.0\ncomment ispars roadmap: {roadmap.poi_count} POIs, digest "
                 f"{roadmap.digest:#018x}\nelement vertex {len(positions)}\nproperty double x\nproperty double y\n"
                 f"property double z\nproperty uint pois\nelement edge {len(edges)}\nproperty uint vertex1\n"
                 f"property uint vertex2\nend_header\n").encode())
        for (x, y, z), k in zip(positions.tolist(), seen.tolist()):
            f.write(f"{x!r} {y!r} {z!r} {k}\n".encode())
        for u, v in edges.tolist():
            f.write(f"{u} {v}\n".encode())

    _write_atomically(path, write)


def save_graphml(roadmap, path):
    """Writes GraphML (networkx.read_graphml, Gephi, yEd, igraph): nodes with x, y, z and pois (the
    POI ids, space-separated), undirected edges with weight (the length)."""
    positions = roadmap.positions.tolist()
    pois = _poi_lists(roadmap)
    header = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<graphml xmlns="http://graphml.graphdrawing.org/xmlns">\n'
        '  <key id="x" for="node" attr.name="x" attr.type="double"/>\n'
        '  <key id="y" for="node" attr.name="y" attr.type="double"/>\n'
        '  <key id="z" for="node" attr.name="z" attr.type="double"/>\n'
        '  <key id="pois" for="node" attr.name="pois" attr.type="string"/>\n'
        '  <key id="weight" for="edge" attr.name="weight" attr.type="double"/>\n'
        f'  <graph id="roadmap" edgedefault="undirected">\n')

    def write(f):
        f.write(header.encode())
        for v, ((x, y, z), seen) in enumerate(zip(positions, pois)):
            ids = " ".join(str(p) for p in seen.tolist())
            f.write((f'    <node id="n{v}"><data key="x">{x!r}</data><data key="y">{y!r}</data>'
                     f'<data key="z">{z!r}</data><data key="pois">{ids}</data></node>\n').encode())
        for k, ((u, v), c) in enumerate(zip(roadmap.edges.tolist(), roadmap.costs.tolist())):
            f.write(f'    <edge id="e{k}" source="n{u}" target="n{v}"><data key="weight">{c!r}</data></edge>\n'.encode())
        f.write(b"  </graph>\n</graphml>\n")

    _write_atomically(path, write)
