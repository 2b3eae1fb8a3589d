"""Anyone's graph in (Roadmap.from_arrays) and out (networkx, scipy, .npz, PLY, GraphML, pickle)."""
import json
import pickle

import numpy as np
import pytest

from conftest import SCENES, run_json

SCENE = SCENES / "truss_bridge.yaml"


def grid(n=6, spacing=2.0):
    """An n x n x 2 grid graph made with numpy: each vertex sees the POI below it, if any."""
    xs, ys, zs = np.meshgrid(np.arange(n), np.arange(n), np.arange(2), indexing="ij")
    positions = np.stack([xs, ys, zs], axis=-1).reshape(-1, 3).astype(float) * spacing
    index = np.arange(len(positions)).reshape(n, n, 2)
    edges = np.concatenate([
        np.stack([index[:-1].ravel(), index[1:].ravel()], axis=1),
        np.stack([index[:, :-1].ravel(), index[:, 1:].ravel()], axis=1),
        np.stack([index[:, :, 0].ravel(), index[:, :, 1].ravel()], axis=1)])
    visibility = [[int(v // 2)] if v % 2 == 0 and (v // 2) % 3 == 0 else [] for v in range(len(positions))]
    return positions, edges, visibility


@pytest.fixture(scope="module")
def built(ispars):
    return ispars.build(ispars.Scene.load(SCENE), 3000, method="ispars", seed=2).roadmap


def test_a_grid_from_arrays_is_that_graph(ispars):
    positions, edges, visibility = grid()
    r = ispars.Roadmap.from_arrays(positions, edges, visibility=visibility)
    assert (r.vertex_count, r.edge_count, r.component_count) == (len(positions), len(edges), 1)
    assert np.array_equal(r.positions, positions) and np.array_equal(r.edges, edges)
    assert np.allclose(r.costs, 2.0)
    assert r.poi_count == max(p for row in visibility for p in row) + 1
    offsets, ids = r.visibility()
    assert [list(ids[offsets[v]:offsets[v + 1]]) for v in range(r.vertex_count)] == visibility
    same = ispars.Roadmap.from_arrays(positions, edges, costs=np.full(len(edges), 2.0), visibility=(offsets, ids))
    assert same.digest == r.digest


def test_a_tour_on_arrays_equals_the_tour_on_the_same_graph_read_from_json(ispars, tmp_path):
    # An OMPL-style PRM made with numpy: random points, each joined to its 6 nearest.
    rng = np.random.default_rng(4)
    points = rng.uniform(0, 20, size=(120, 3))
    d = np.linalg.norm(points[:, None] - points[None], axis=2)
    near = np.argsort(d, axis=1)[:, 1:7]
    pairs = {tuple(sorted((i, int(j)))) for i in range(len(points)) for j in near[i]}
    edges = np.array(sorted(pairs))
    pois = rng.uniform(0, 20, size=(30, 3))
    visibility = [list(np.flatnonzero(np.linalg.norm(pois - p, axis=1) < 4.0)) for p in points]
    r = ispars.Roadmap.from_arrays(points, edges, visibility=visibility, poi_count=len(pois))
    path = tmp_path / "prm.json"
    r.save(path, "prm", points[0], pois)
    # The budget lets the LP bound run to its end after the 60 iterations: a bound of its own.
    ours = ispars.tour(r, budget=60, iterations=60, seed=3)
    read = ispars.tour(ispars.load_roadmap(path), budget=60, iterations=60, seed=3)
    lab = run_json("ispars-lab", "tour", path, "--budget", 60, "--iterations", 60, "--seed", 3, "--json")
    assert ours["valid"] and ours["bound_complete"] and ours["lower_bound"] is not None
    assert ours["cost"] == read["cost"] and ours["lower_bound"] == read["lower_bound"]
    assert ours["cost"] == pytest.approx(lab["cost"], rel=1e-12)
    assert ours["lower_bound"] <= ours["cost"] + 1e-9


@pytest.mark.parametrize("change, field", [
    (lambda p, e, v: (p[:, :2], e, v), "positions"),
    (lambda p, e, v: (np.empty((0, 3)), np.empty((0, 2), int), []), "positions"),
    (lambda p, e, v: (np.where(np.arange(len(p))[:, None] == 3, np.nan, p), e, v), "positions[3]"),
    (lambda p, e, v: (p, e.astype(float) + 0.5, v), "edges"),
    (lambda p, e, v: (p, np.vstack([e, [[0, len(p)]]]), v), f"edges[{0}]"),
    (lambda p, e, v: (p, np.vstack([e, [[5, 5]]]), v), "edges"),
    (lambda p, e, v: (p, np.vstack([e, e[:1, ::-1]]), v), "edges"),
    (lambda p, e, v: (p, e, v[:-1]), "visibility"),
    (lambda p, e, v: (p, e, [[1.5]] + v[1:]), "visibility[0]"),
    (lambda p, e, v: (p, e, [[-1]] + v[1:]), "visibility[0]"),
])
def test_bad_arrays_are_refused_by_name(ispars, change, field):
    positions, edges, visibility = change(*grid(3))
    with pytest.raises(ispars.InputError) as e:
        ispars.Roadmap.from_arrays(positions, edges, visibility=visibility)
    assert e.value.file == "from_arrays" and e.value.field.startswith(field.split("[")[0]), str(e.value)


def test_costs_must_be_the_lengths_and_poi_count_must_cover_the_ids(ispars):
    positions, edges, visibility = grid(3)
    costs = np.full(len(edges), 2.0)
    costs[4] = 2.5
    with pytest.raises(ispars.InputError, match=r"costs\[4\]: is 2.5, but the edge is 2 long"):
        ispars.Roadmap.from_arrays(positions, edges, costs=costs)
    with pytest.raises(ispars.InputError, match="poi_count"):
        ispars.Roadmap.from_arrays(positions, edges, visibility=visibility, poi_count=1)
    with pytest.raises(ispars.InputError, match="repeats an earlier edge"):
        ispars.Roadmap.from_arrays(positions, np.vstack([edges, edges[2:3, ::-1]]))


def test_components_are_labels_numbered_from_the_root(ispars):
    positions = np.array([[0, 0, 0], [1, 0, 0], [5, 0, 0], [6, 0, 0], [9, 0, 0]], float)
    r = ispars.Roadmap.from_arrays(positions, [[2, 3], [0, 1]])
    assert list(r.components()) == [0, 0, 1, 1, 2]
    assert r.component_count == 3


def test_exports_are_the_same_graph(ispars, built, tmp_path):
    nx = pytest.importorskip("networkx")
    csgraph = pytest.importorskip("scipy.sparse.csgraph")
    g = built.to_networkx()
    assert (g.number_of_nodes(), g.number_of_edges()) == (built.vertex_count, built.edge_count)
    u, v = (int(x) for x in built.edges[7])
    assert g[u][v]["weight"] == pytest.approx(built.costs[7])
    assert g.nodes[5]["pois"] == list(built.pois_of(5))
    m = built.to_scipy()
    assert m.shape == (built.vertex_count,) * 2 and m.nnz == 2 * built.edge_count
    count, labels = csgraph.connected_components(m, directed=False)
    assert count == built.component_count and np.array_equal(labels, built.components())
    dist = csgraph.dijkstra(m, indices=0)
    assert dist[u] == pytest.approx(nx.single_source_dijkstra_path_length(g, 0, weight="weight")[u])

    built.save_graphml(tmp_path / "r.graphml")
    back = nx.read_graphml(tmp_path / "r.graphml")
    assert (back.number_of_nodes(), back.number_of_edges()) == (built.vertex_count, built.edge_count)
    seeing = next(v for v in range(built.vertex_count) if len(built.pois_of(v)) > 1)
    assert back.nodes[f"n{seeing}"]["pois"] == " ".join(str(p) for p in built.pois_of(seeing))
    assert back["n%d" % u]["n%d" % v]["weight"] == pytest.approx(built.costs[7], rel=1e-15)

    built.save_ply(tmp_path / "r.ply")
    text = (tmp_path / "r.ply").read_text().splitlines()
    end = text.index("end_header")
    assert f"element vertex {built.vertex_count}" in text and f"element edge {built.edge_count}" in text
    rows = np.array([[float(x) for x in line.split()] for line in text[end + 1:end + 1 + built.vertex_count]])
    assert np.array_equal(rows[:, :3], built.positions)
    assert np.array_equal(rows[:, 3], np.diff(built.visibility()[0])), "each vertex's POI count"
    assert [int(x) for x in text[-1].split()] == list(built.edges[-1])


def test_npz_and_pickle_keep_the_digest_and_damage_is_named(ispars, built, tmp_path):
    path = tmp_path / "r.npz"
    built.save_npz(path)
    back = ispars.load_npz(path)
    assert back.digest == built.digest and back.version == built.version
    assert pickle.loads(pickle.dumps(built)).digest == built.digest
    data = dict(np.load(path))
    data["positions"] = data["positions"] + 1e-9
    np.savez(tmp_path / "moved.npz", **data)
    with pytest.raises(ispars.InputError) as e:
        ispars.load_npz(tmp_path / "moved.npz")
    assert e.value.field == "digest"
    (tmp_path / "junk.npz").write_bytes(b"not a zip")
    with pytest.raises(ispars.InputError) as e:
        ispars.load_npz(tmp_path / "junk.npz")
    assert e.value.field == "file"
    np.savez(tmp_path / "other.npz", a=np.zeros(3))
    with pytest.raises(ispars.InputError, match="not an ispars roadmap"):
        ispars.load_npz(tmp_path / "other.npz")


def test_scene_exposes_its_mesh_radius_and_range(ispars):
    scene = ispars.Scene.load(SCENE)
    vertices, triangles = scene.mesh
    assert vertices.dtype == np.float32 and vertices.shape[1] == 3 and triangles.shape[1] == 3
    assert triangles.max() < len(vertices) and not vertices.flags.writeable
    config = json.loads(json.dumps({"r": scene.robot_radius, "s": scene.sensor_range}))
    assert config["r"] > 0 and config["s"] > config["r"]
