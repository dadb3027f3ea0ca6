#!/usr/bin/env python3
"""Cuts holes from a complete cloth mesh and fills each with foldfill: how often
the start must be untangled, and whether any fill crosses anything.

  python3 bench/sweep_holes.py FOLDFILL MESH.obj OUT_DIR [--holes N] [--seed S]

Each hole is a geodesic disk (Dijkstra on the edges) of 8 to 16 mean edge
lengths around a random vertex at least 6 edges from the mesh's boundary; the
fill is asked for the loop nearest that vertex (--near). Prints one line per
hole (method, start, crossings, iterations, seconds) and a summary.
"""
import argparse, heapq, json, os, random, subprocess, sys
from collections import Counter


def load(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            s = line.split()
            if not s:
                continue
            if s[0] == "v":
                vertices.append(tuple(float(x) for x in s[1:4]))
            elif s[0] == "f":
                faces.append(tuple(int(x.split("/")[0]) - 1 for x in s[1:4]))
    return vertices, faces


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("foldfill")
    parser.add_argument("mesh")
    parser.add_argument("out")
    parser.add_argument("--holes", type=int, default=10)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    vertices, faces = load(args.mesh)
    n = len(vertices)
    length = lambda a, b: sum((vertices[a][c] - vertices[b][c]) ** 2 for c in range(3)) ** 0.5
    neighbours = [[] for _ in range(n)]
    edges = Counter()
    for f in faces:
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            neighbours[a].append((b, length(a, b)))
            edges[(min(a, b), max(a, b))] += 1
    boundary = {v for e, count in edges.items() if count == 1 for v in e}
    mean_edge = sum(d for row in neighbours for _, d in row) / sum(len(r) for r in neighbours)

    def within(seed, radius):
        dist, heap = {seed: 0.0}, [(0.0, seed)]
        while heap:
            d, v = heapq.heappop(heap)
            if d > dist[v]:
                continue
            for w, l in neighbours[v]:
                if d + l <= radius and d + l < dist.get(w, float("inf")):
                    dist[w] = d + l
                    heapq.heappush(heap, (d + l, w))
        return dist

    os.makedirs(args.out, exist_ok=True)
    rng = random.Random(args.seed)
    rows, made = [], 0
    while made < args.holes:
        seed = rng.randrange(n)
        radius = mean_edge * rng.uniform(8, 16)
        if within(seed, radius + 6 * mean_edge).keys() & boundary:
            continue
        inside = set(within(seed, radius))
        kept = [f for f in faces if not all(v in inside for v in f)]
        used = sorted({v for f in kept for v in f})
        index = {v: k for k, v in enumerate(used)}
        name = os.path.join(args.out, "hole%02d" % made)
        with open(name + ".obj", "w") as f:
            f.writelines("v %.17g %.17g %.17g\n" % vertices[v] for v in used)
            f.writelines("f %d %d %d\n" % tuple(index[v] + 1 for v in t) for t in kept)
        made += 1
        near = ["%.17g" % x for x in vertices[seed]]
        run = subprocess.run([args.foldfill, "fill", name + ".obj", "--near", *near, "-o",
                              name + "_filled.obj", "--report", name + ".json", "-q"],
                             capture_output=True, text=True)
        if run.returncode not in (0, 9):
            print(name, "exit", run.returncode, run.stderr.strip())
            continue
        for hole in json.load(open(name + ".json"))["holes"]:
            if not hole.get("filled"):
                continue
            c = hole["crossings"]
            rows.append((hole["method"], hole.get("start"), c["patch_patch"] + c["patch_mesh"] + c["patch_obstacles"]))
            print(os.path.basename(name), hole["method"], hole.get("start"), c, hole.get("iterations"),
                  "%.2f s" % hole["seconds"]["total"])
    starts = Counter(r[1] for r in rows)
    methods = Counter(r[0] for r in rows)
    print("holes %d; methods %s; starts %s; holes that cross something: %d"
          % (len(rows), dict(methods), dict(starts), sum(r[2] > 0 for r in rows)))


if __name__ == "__main__":
    sys.exit(main())
