#!/usr/bin/env python3
"""The Python package's costs, printed as one JSON object:

  arrays  a roadmap of at least 100,000 vertices (Dense on water_tower) into numpy: the copy out
          of the builder, then each array, timed, with the Python objects allocated meanwhile
          (sys.getallocatedblocks); beside it the JSON route a script took before the package
          (the roadmap file, json.load, numpy.array);
  stats   the STATS round trip to a real isparsd from Python (Client.stats) against the C++
          client's in the same process on the same connection, alternating blocks of 100;
  import  `import ispars` in a fresh interpreter, the median of 10;
  stops   how long after Stop.set() an extend, a verify and a tour return (water_tower, ispars).

Usage: bench_python.py [--samples N] [--calls N] [--skip-arrays] [--skip-stats]; run from the
source tree after a build (PYTHONPATH=build/python), with build/bin/isparsd for `stats`.
"""
import argparse
import json
import os
import pathlib
import signal
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[3]
sys.path.insert(0, os.environ.get("ISPARS_PYTHON_PATH", str(ROOT / "build" / "python")))
sys.path.insert(0, str(ROOT / "tests" / "python"))  # the tests' domain locks and daemon start
import numpy as np  # noqa: E402

import ispars  # noqa: E402


def timed(f):
    blocks = sys.getallocatedblocks()
    t0 = time.perf_counter()
    value = f()
    return value, time.perf_counter() - t0, sys.getallocatedblocks() - blocks


def bench_arrays(samples):
    scene = ispars.Scene.load(str(ROOT / "deploy/scenes/water_tower.yaml"))
    builder = ispars.Builder(scene, method="dense", seed=1, threads=2)
    t0 = time.perf_counter()
    builder.extend(samples)
    build_seconds = time.perf_counter() - t0
    roadmap, copy_s, _ = timed(lambda: builder.roadmap)
    out = {"roadmap_vertices": roadmap.vertex_count, "roadmap_edges": roadmap.edge_count, "build_seconds": build_seconds,
           "copy_out_of_builder_seconds": copy_s}
    for name, get in [("positions", lambda: roadmap.positions), ("edges", lambda: roadmap.edges),
                      ("costs", lambda: roadmap.costs), ("visibility", roadmap.visibility),
                      ("components", roadmap.components)]:
        value, seconds, blocks = timed(get)
        arrays = value if isinstance(value, tuple) else (value,)
        out[name] = {"seconds": seconds, "python_blocks_allocated": blocks,
                     "bytes": int(sum(a.nbytes for a in arrays)),
                     "view": bool(not arrays[0].flags.owndata and arrays[0].base is not None
                                  and name in ("positions", "edges"))}
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "roadmap.json"
        roadmap.save(str(path), scene.name, scene.root, scene.pois)

        def via_json():
            g = json.loads(path.read_text())["graphs"]["roadmap"]
            return np.array(g["vertices"], dtype=np.float64), np.array([e[:2] for e in g["edges"]], dtype=np.uint32)
        (positions, edges), json_s, _ = timed(via_json)
        assert np.array_equal(positions, roadmap.positions) and np.array_equal(edges, roadmap.edges)
        out["json_route_seconds"] = json_s
        out["json_file_bytes"] = path.stat().st_size
    return out


def bench_stops():
    """How long after Stop.set() each long call returns: extend, verify and tour on water_tower."""
    import threading
    scene = ispars.Scene.load(str(ROOT / "deploy/scenes/water_tower.yaml"))
    builder = ispars.Builder(scene, method="ispars", seed=1)
    out = {}

    def latency(call, after):
        stop = ispars.Stop()
        stamp = {}

        def set_stop():
            stamp["set"] = time.perf_counter()
            stop.set()
        threading.Timer(after, set_stop).start()
        try:
            call(stop)
        except RuntimeError as e:  # a stopped verification raises
            assert "stopped" in str(e)
        return time.perf_counter() - stamp["set"]
    out["extend_seconds"] = latency(lambda stop: builder.extend(100_000_000, stop=stop), 3.0)
    out["extend_samples_when_stopped"] = builder.samples
    out["verify_seconds"] = latency(lambda stop: builder.verify(stop=stop), 0.5)
    roadmap = builder.roadmap
    out["tour_seconds"] = latency(lambda stop: ispars.tour(roadmap, budget=600, stop=stop), 2.0)
    return out


def bench_stats(calls):
    from conftest import BIN, SCENES, _take_domain, wait_for_daemon
    domain = _take_domain()
    with tempfile.TemporaryDirectory() as tmp:
        daemon = subprocess.Popen([str(BIN / "isparsd"), "--domain", str(domain), "--data-dir", tmp + "/data",
                                   "--scene-dir", str(SCENES), "--server-id", "bench", "--log-level", "warn"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            client = ispars.Client(domain=domain, timeout=30)
            wait_for_daemon(client, "bench")
            client.load("truss_bridge")
            client.build("truss_bridge", 2000)
            client.wait_idle("truss_bridge", timeout=120)
            python, cpp = [], []
            for _ in range(max(1, calls // 100)):
                for _ in range(100):
                    t0 = time.perf_counter()
                    client.stats("truss_bridge")
                    python.append(time.perf_counter() - t0)
                cpp += client._bench_stats("truss_bridge", 100)
        finally:
            daemon.send_signal(signal.SIGTERM)
            daemon.wait(timeout=30)
    summary = {}
    for name, xs in (("python", python), ("cpp", cpp)):
        xs = sorted(xs)
        summary[name] = {"calls": len(xs), "median_us": 1e6 * statistics.median(xs),
                         "p90_us": 1e6 * xs[int(0.9 * (len(xs) - 1))], "mean_us": 1e6 * statistics.fmean(xs)}
    summary["python_over_cpp_median_us"] = summary["python"]["median_us"] - summary["cpp"]["median_us"]
    summary["python_over_cpp_ratio"] = summary["python"]["median_us"] / summary["cpp"]["median_us"]
    return summary


def bench_import():
    env = dict(os.environ, PYTHONPATH=str(ROOT / "build" / "python"))
    code = "import time; t = time.perf_counter(); import ispars; print(time.perf_counter() - t)"
    runs = [float(subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                                 check=True).stdout) for _ in range(10)]
    return {"median_seconds": statistics.median(runs), "min_seconds": min(runs), "runs": len(runs)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=102_000, help="Dense samples (102,000 give over 100,000 vertices)")
    parser.add_argument("--calls", type=int, default=2000, help="STATS round trips from each side")
    parser.add_argument("--skip-arrays", action="store_true")
    parser.add_argument("--skip-stats", action="store_true")
    args = parser.parse_args()
    out = {"python": sys.version.split()[0], "numpy": np.__version__, "import": bench_import()}
    if not args.skip_arrays:
        out["arrays"] = bench_arrays(args.samples)
    if not args.skip_stats:
        out["stats"] = bench_stats(args.calls)
    out["stops"] = bench_stops()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
