"""The client against real isparsd processes: build, watch, snapshot, tour, the same roadmap as the
offline builder, refusals named by the daemon, and a viewer's change refused."""
import subprocess
import threading

import numpy as np
import pytest

from conftest import PACKAGE_DIR, SCENES, SOURCE_DIR, wait_for_daemon
from test_tour_model import check_model

SCENE = "truss_bridge"


@pytest.fixture
def served(ispars, domain, daemon_factory):
    daemon = daemon_factory(domain)
    client = ispars.Client(domain=domain, timeout=30)
    wait_for_daemon(client, "py")
    client.load(SCENE)
    return client, daemon


def test_a_watched_build_equals_its_snapshot_stats_and_the_offline_build(ispars, served):
    client, _ = served
    watch = client.watch(SCENE)
    reply = client.build(SCENE, 6000, method="ispars", seed=4)
    assert reply["server_id"] == "py"
    seen = {"positions": [], "edges": []}
    vertices = edges = 0
    for batch in watch:
        if batch["resynced"]:
            seen = {"positions": [], "edges": []}
        assert batch["first_vertex"] == sum(len(p) for p in seen["positions"])
        seen["positions"].append(batch["positions"])
        seen["edges"].append(batch["edges"])
        vertices, edges = batch["vertex_count"], batch["edge_count"]
        if batch["samples_done"] >= 6000:
            break
    status = client.wait_idle(SCENE, timeout=120)
    snapshot = client.snapshot(SCENE)
    roadmap = snapshot["roadmap"]
    assert (status.vertices, status.edges, status.version) == (roadmap.vertex_count, roadmap.edge_count,
                                                              snapshot["version"])
    assert (vertices, edges) == (roadmap.vertex_count, roadmap.edge_count)
    assert np.array_equal(np.concatenate(seen["positions"]), roadmap.positions)
    assert np.array_equal(np.concatenate(seen["edges"]), roadmap.edges)
    assert watch.roadmap().digest == roadmap.digest
    watch.close()
    assert list(watch) == []
    offline = ispars.build(str(SCENES / f"{SCENE}.yaml"), 6000, method="ispars", seed=4)
    assert offline.roadmap.digest == roadmap.digest
    assert np.array_equal(snapshot["pois"], offline.scene.pois)


def test_a_tour_reports_progress_and_a_valid_walk(ispars, served):
    client, _ = served
    client.build(SCENE, 4000, method="ispars2", seed=2)
    client.wait_idle(SCENE, timeout=120)
    seen = []
    tour = client.tour(SCENE, budget=1.0, progress=lambda t, cost, bound: seen.append((t, cost, bound)))
    assert tour["valid"] and tour["cost"] > 0
    assert seen and seen[-1][1] == pytest.approx(tour["cost"])
    # One tour model: the offline tour's keys and types, with the reply's beside them; progress
    # from the first tour on (never a cost of 0), the bound None until one is proven.
    check_model(tour, {"server_id", "message", "status"})
    assert tour["flown"] is True and tour["problem"] == ""
    assert all(cost > 0 for _, cost, _ in seen)
    assert all(bound is None or bound > 0 for _, _, bound in seen)
    assert tour["walk"][0] == 0 and tour["walk"][-1] == 0
    assert tour["waypoints"].shape == (len(tour["walk"]), 3)
    # The flown tour: closed at the root, no longer than the shortcut or the walk, each stop's targets.
    assert 0 < tour["flown_cost"] <= tour["shortcut_cost"] <= tour["cost"]
    assert np.array_equal(tour["flown_path"][0], tour["flown_path"][-1])
    assert len(tour["flown_sees"]) == len(tour["flown_path"])
    assert [s["stage"] for s in tour["stages"]][:2] == ["walk", "shortcut"]
    assert tour["stages"][-1]["cost"] == pytest.approx(tour["flown_cost"])
    path = client.path(SCENE, [0, -12, 1.5], tour["waypoints"][len(tour["walk"]) // 2])
    assert path["length"] > 0 and path["waypoints"].shape[1] == 3
    assert client.verify(SCENE)["violations"] == 0


def test_the_daemon_refusals_are_named_and_change_nothing(ispars, served):
    client, _ = served
    client.build(SCENE, 2000, seed=1)
    before = client.wait_idle(SCENE, timeout=120)
    # A request the typed form cannot hold, or a value out of its declared range, is refused
    # before it is sent, with the daemon's own words (make_recipe's checks run there again).
    with pytest.raises(ispars.InputError, match="method: 'prm' is not one of dense, spars, ispars, irisc, ispars2"):
        client.build(SCENE, 100, method="prm", replace=True)
    with pytest.raises(ispars.InputError, match=r"overrides.dense_delta: must be in \(0, 1000000\], got -1"):
        client.build(SCENE, 100, overrides={"dense_delta": -1}, replace=True)
    with pytest.raises(ispars.ClientError, match="overrides.sparse_delta: 100000 is larger than the scene's diagonal") as e:
        client.build(SCENE, 100, overrides={"sparse_delta": 1e5}, replace=True)  # the scene's checks: the daemon's
    assert e.value.kind == "rejected"
    with pytest.raises(ispars.ClientError) as e:
        client.stats("no_such_scene")
    assert e.value.kind in ("rejected", "no_daemon")
    after = client.stats(SCENE)
    assert (after.generation, after.version) == (before.generation, before.version)


def test_a_dead_daemon_raises_a_client_error(ispars, served):
    client, daemon = served
    assert daemon.stop() == 0
    quick = ispars.Client(domain=daemon.domain, timeout=2)
    with pytest.raises(ispars.ClientError) as e:
        quick.stats(SCENE)
    assert e.value.kind in ("no_daemon", "timeout"), str(e.value)


def test_a_viewer_may_look_but_its_changes_raise_forbidden(ispars, domain, daemon_factory, tmp_path):
    keystore = tmp_path / "keystore"
    subprocess.run([str(SOURCE_DIR / "deploy/security/make-keystore.sh"), str(keystore), "daemon:d",
                    "viewer:view"], check=True, capture_output=True)
    daemon_factory(domain, server_id="d", extra=("--security", str(keystore / "identities/d")))
    viewer = ispars.Client(domain=domain, security=str(keystore / "identities/view"), timeout=30)
    wait_for_daemon(viewer, "d", seconds=60)
    with pytest.raises(ispars.ClientError) as e:
        viewer.load(SCENE)
    assert e.value.kind == "forbidden"
    assert "permissions do not allow load" in str(e.value)
    assert not any(s["loaded"] for s in viewer.scenes() if s["scene"] == SCENE)


def test_ctrl_c_during_a_wait_returns_at_once(ispars, served):
    import os
    import signal
    import time
    client, _ = served
    client.build(SCENE, 2000, seed=1)
    client.wait_idle(SCENE, timeout=120)
    watch = client.watch(SCENE)
    watch.next(timeout=30)  # the first batch: the whole roadmap
    threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        next(watch)  # no build runs: no batch would come
    assert time.monotonic() - started < 5
    assert watch.next(timeout=0.2) is None


def test_the_documented_example_runs_against_a_daemon(domain, daemon_factory, tmp_path):
    import os
    import sys
    daemon_factory(domain)
    env = dict(os.environ, PYTHONPATH=PACKAGE_DIR)
    out = subprocess.run([sys.executable, str(SOURCE_DIR / "docs/python_example.py"), "--domain", str(domain),
                          "--samples", "3000", "--budget", "0.3", "--out", str(tmp_path / "tour.png")],
                         env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert "tour: cost" in out.stdout and (tmp_path / "tour.png").exists()


def test_extend_cancel_and_unload(ispars, served):
    client, _ = served
    client.build(SCENE, 3000, method="ispars2", seed=5)
    client.wait_idle(SCENE, timeout=120)
    client.extend(SCENE, 2000)
    status = client.wait_idle(SCENE, timeout=120)
    assert status.samples_done == 5000 and status.state == "idle"
    offline = ispars.build(str(SCENES / f"{SCENE}.yaml"), 5000, method="ispars2", seed=5)
    assert client.snapshot(SCENE)["roadmap"].digest == offline.roadmap.digest
    with pytest.raises(ispars.ClientError, match="samples: the roadmap would hold about .* memory budget"):
        client.extend(SCENE, 50_000_000)  # refused before it starts: the memory budget
    client.extend(SCENE, 1_000_000)  # far more than the test waits for
    reply = client.cancel(SCENE)
    assert reply["server_id"] == "py"
    cancelled = client.wait_idle(SCENE, timeout=60)
    assert 5000 <= cancelled.samples_done < 1_005_000 and cancelled.state == "idle"
    client.unload(SCENE)
    with pytest.raises(ispars.ClientError) as e:
        client.stats(SCENE)
    assert "not loaded" in str(e.value), str(e.value)


def test_closing_a_watch_from_another_thread_ends_its_iteration(ispars, served):
    client, _ = served
    client.build(SCENE, 1000, seed=1)
    client.wait_idle(SCENE, timeout=120)
    watch = client.watch(SCENE)
    assert watch.next(timeout=30)["vertex_count"] > 0
    rest = []
    follower = threading.Thread(target=lambda: rest.extend(watch))  # blocks: no build runs
    follower.start()
    threading.Timer(0.3, watch.close).start()
    follower.join(timeout=10)
    assert not follower.is_alive() and rest == []
    with pytest.raises(RuntimeError, match="the watch is closed"):
        watch.roadmap()


def test_client_arguments_are_input_errors_and_a_client_closes(ispars, served):
    client, _ = served
    for call, field in [(lambda: client.build(SCENE, -5), "samples"), (lambda: client.build(SCENE, 2.5), "samples"),
                        (lambda: client.extend(SCENE, 2**64), "samples"),
                        (lambda: client.build(SCENE, 100, seed=-1), "seed"),
                        (lambda: client.tour(SCENE, budget=0), "budget"),
                        (lambda: client.tour(SCENE, targets=[1.5]), "targets"),
                        (lambda: ispars.Client(domain="231"), "domain"),
                        (lambda: ispars.Client(domain=233), "domain")]:
        with pytest.raises(ispars.InputError) as e:
            call()
        assert e.value.field == field, str(e.value)
    with ispars.Client(domain=served[1].domain, timeout=10) as scoped:
        wait_for_daemon(scoped, "py")
        assert not scoped.closed
    assert scoped.closed
    with pytest.raises(RuntimeError, match="closed"):
        scoped.stats(SCENE)
    scoped.close()  # again: nothing
    assert client.stats(SCENE).scene == SCENE, "another client is untouched"


def test_a_bad_profile_file_is_an_input_error(ispars, tmp_path, capfd):
    with pytest.raises(ispars.InputError) as e:
        ispars.Client(domain=1, profile_file=str(tmp_path / "missing.xml"))
    assert e.value.field == "profile_file" and "cannot be read" in str(e.value)
    bad = tmp_path / "bad.xml"
    bad.write_text("<dds><profiles><participant profile_name='x'><rtps><oops/></rtps></participant></profiles></dds>")
    with pytest.raises(ispars.InputError) as e:
        ispars.Client(domain=1, profile_file=str(bad), profile_name="ispars")
    assert e.value.file == str(bad) and e.value.field == "profile_file"
    captured = capfd.readouterr()  # Fast DDS's own console output went to stdout, in colour
    assert "\x1b[" not in captured.out + captured.err, "no colour codes: " + repr(captured.out[:200])
    assert "ispars: error: fastdds [XMLPARSER]" in captured.err, captured.err[:400]


def test_tasks_are_added_listed_toured_and_removed(ispars, served):
    client, _ = served
    client.build(SCENE, 3000, method="ispars2", seed=3)
    client.wait_idle(SCENE, timeout=120)
    before = client.stats(SCENE).poi_count
    client.add_task(SCENE, "cracks", sample=40, seed=8)
    pois = client.snapshot(SCENE)["pois"][:5]
    client.wait_idle(SCENE, timeout=120)
    client.add_task(SCENE, "copies", pois=pois)
    status = client.wait_idle(SCENE, timeout=120)
    assert (status.tasks, status.poi_count) == (2, before + 45), (status.tasks, status.poi_count, before)
    tasks = client.tasks(SCENE)
    assert [t["name"] for t in tasks] == ["cracks", "copies"], tasks
    assert (tasks[0]["first_poi"], tasks[0]["poi_count"]) == (before, 40), tasks[0]
    assert tasks[1]["first_poi"] == before + 40 and tasks[1]["pois_covered"] == 5, tasks[1]
    tour = client.tour(SCENE, budget=2.0, task="copies")
    check_model(tour, {"server_id", "message", "status"})
    assert tour["target_count"] == tasks[1]["pois_covered_root"] > 0, (tour["target_count"], tasks[1])
    client.remove_task(SCENE, "copies")
    assert [t["name"] for t in client.tasks(SCENE)] == ["cracks"]
    with pytest.raises(ispars.ClientError, match="copies"):
        client.remove_task(SCENE, "copies")
    for call, field in [(lambda: client.add_task(SCENE, "x"), "pois"),
                        (lambda: client.add_task(SCENE, "x", pois=pois, sample=3), "pois"),
                        (lambda: client.add_task(SCENE, "x", sample=5001), "sample"),
                        (lambda: client.add_task(SCENE, "x", sample=2.5), "sample"),
                        (lambda: client.add_task(SCENE, "x", sample=3, seed=-1), "seed"),
                        (lambda: client.add_task(SCENE, "x", pois=np.zeros((0, 3))), "pois")]:
        with pytest.raises(ispars.InputError) as e:
            call()
        assert e.value.field == field, str(e.value)
    assert client.stats(SCENE).tasks == 1, "nothing refused reached the daemon"


def test_watching_a_scene_no_daemon_holds_raises_at_once(ispars, served):
    client, _ = served
    with pytest.raises(ispars.ClientError, match="no_such_scene"):
        client.watch("no_such_scene")


def test_a_watch_of_an_idle_scene_delivers_its_roadmap_once(ispars, served):
    client, _ = served
    client.build(SCENE, 1500, method="ispars2", seed=6)
    status = client.wait_idle(SCENE, timeout=120)
    for _ in range(2):  # a new client, and one that watched before
        fresh = ispars.Client(domain=served[1].domain, timeout=30)
        for watcher in (fresh, client):
            with watcher.watch(SCENE) as watch:
                first = watch.next(timeout=30)
                assert first["resynced"] and first["vertex_count"] == status.vertices == len(first["positions"])
                assert watch.next(timeout=3) is None, "an idle scene's roadmap comes once, not again"
        fresh.close()


def test_an_offline_path_on_the_snapshot_is_the_daemons_path(ispars, served):
    client, _ = served
    client.build(SCENE, 2000, method="ispars2", seed=7)
    client.wait_idle(SCENE, timeout=120)
    roadmap = client.snapshot(SCENE)["roadmap"]
    goal = roadmap.positions[np.flatnonzero(roadmap.components() == 0)[-1]]
    online = client.path(SCENE, roadmap.positions[0], goal)
    offline = ispars.path(str(SCENES / f"{SCENE}.yaml"), roadmap, roadmap.positions[0], goal)
    assert offline["length"] == online["length"]
    assert np.array_equal(offline["waypoints"], online["waypoints"])
