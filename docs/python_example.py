#!/usr/bin/env python3
"""ispars from Python: build an Inspection-SPARS roadmap offline, verify it, search a tour, and
plot it (matplotlib when present, else ispars.render's PNG). With --domain it does the same
through a running isparsd instead, following the build live.

    python3 docs/python_example.py [--samples N] [--out tour.png]   # after pip install . (docs/python.md)
    python3 docs/python_example.py --domain 42                       # against isparsd
"""
import argparse
import pathlib

import numpy as np

import ispars

ROOT = pathlib.Path(__file__).resolve().parents[1]


def offline(scene_file, samples, seed):
    scene = ispars.Scene.load(scene_file)
    builder = ispars.build(scene, samples, method="ispars", seed=seed,
                           progress=lambda done, total, v, e: print(f"\r{done}/{total} samples, {v} vertices, "
                                                                    f"{e} edges", end="", flush=True))
    print()
    roadmap, dense = builder.roadmap, builder.dense
    print(f"{roadmap.vertex_count} vertices and {roadmap.edge_count} edges; the dense pair has "
          f"{dense.vertex_count / roadmap.vertex_count:.1f}x the vertices and "
          f"{dense.edge_count / max(1, roadmap.edge_count):.1f}x the edges")
    print("verify:", builder.verify())
    return scene, roadmap


def online(domain, scene_name, samples, seed):
    client = ispars.Client(domain=domain)
    client.load(scene_name)
    watch = client.watch(scene_name)
    client.build(scene_name, samples, method="ispars", seed=seed, replace=True)
    for batch in watch:  # what each committed batch added, as numpy arrays
        print(f"\r+{len(batch['positions'])} vertices, +{len(batch['edges'])} edges: "
              f"{batch['samples_done']}/{samples} samples", end="", flush=True)
        if batch["samples_done"] >= samples:
            break
    print()
    watch.close()
    print(client.wait_idle(scene_name))
    snapshot = client.snapshot(scene_name)
    return ispars.Scene.load(ROOT / "deploy" / "scenes" / f"{scene_name}.yaml"), snapshot["roadmap"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="truss_bridge", help="a scene of deploy/scenes/")
    parser.add_argument("--samples", type=int, default=20000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--domain", type=int, help="use the isparsd daemons on this DDS domain")
    parser.add_argument("--budget", type=float, default=2.0, help="seconds of tour search")
    parser.add_argument("--out", default="tour.png")
    args = parser.parse_args()

    if args.domain is None:
        scene, roadmap = offline(ROOT / "deploy" / "scenes" / f"{args.scene}.yaml", args.samples, args.seed)
    else:
        scene, roadmap = online(args.domain, args.scene, args.samples, args.seed)
    tour = ispars.tour(roadmap, budget=args.budget)  # Ctrl-C stops it (KeyboardInterrupt)
    print(f"tour: cost {tour['cost']:.2f} over {len(tour['walk']) - 1} edges, seeing {tour['covered']} "
          f"of {tour['target_count']} targets; proven lower bound {tour['lower_bound']}")
    walk = roadmap.positions[tour["walk"]]  # numpy fancy indexing on a read-only view: no loop
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        ispars.render(scene, roadmap=roadmap, tour=walk, path=args.out)
        print(f"wrote {args.out} (ispars.render; matplotlib is not installed)")
        return
    figure = plt.figure(figsize=(8, 6))
    axes = figure.add_subplot(projection="3d")
    p, e = roadmap.positions, roadmap.edges
    segments = np.stack([p[e[:, 0]], p[e[:, 1]]], axis=1)
    for a, b in segments[:: max(1, len(segments) // 5000)]:  # at most about 5,000 edges drawn
        axes.plot(*zip(a, b), color="tab:blue", linewidth=0.3, alpha=0.4)
    axes.scatter(*scene.pois.T, s=2, color="tab:green", label="POIs")
    axes.plot(*walk.T, color="tab:orange", linewidth=2, label=f"tour {tour['cost']:.1f}")
    axes.legend()
    figure.savefig(args.out, dpi=100)
    print(f"wrote {args.out} (matplotlib)")


if __name__ == "__main__":
    main()
