#!/usr/bin/env python3
"""Sheets draped over an analytic obstacle (a cylinder or a sphere, with a floor
plane below), with a hole cut where the sheet rests on it, filled by foldfill
with those obstacles: whether the fill stays outside them and crosses nothing,
and how long it takes (median of several runs), at unit scale and scaled by
1000.

  python3 bench/drape_obstacles.py FOLDFILL OUT_DIR [--cells N] [--hole-radius R] [--runs K]

The sheet is a grid of N x N cells over [-2, 2]^2 lying 0.15 cell above an
obstacle of radius 1 (falling off past its side), wrinkled away from the
contact; the hole is a disk of radius R around a point on the contact. Prints
one line per case: new vertices, the least signed distance of a new vertex to
the obstacles (in cells), the report's crossings, start, iterations and the
median fill time.
"""
import argparse, json, math, os, subprocess, statistics


def sheet(kind, cells, scale, hole_radius):
    h = 4.0 / cells
    radius, gap = 1.0, 0.15 * h

    def height(x, y):
        r = abs(x) if kind == "cylinder" else math.hypot(x, y)
        top = radius + gap
        if r < 0.95 * top:
            z = math.sqrt(top * top - r * r)
        else:
            z = math.sqrt(top * top - (0.95 * top) ** 2) - 1.2 * (r - 0.95 * top)
        wrinkle = 0.25 * h * (1 + math.sin(3.1 * x + 1.7 * y)) * min(1, max(0, (r - 0.5) / 0.4))
        return z + wrinkle

    index, vertices = {}, []
    for i in range(cells + 1):
        for j in range(cells + 1):
            x, y = -2 + i * h, -2 + j * h
            index[i, j] = len(vertices)
            vertices.append((x, y, height(x, y)))
    centre = (0.35, 0.1) if kind == "cylinder" else (0.3, 0.2)
    faces = []
    for i in range(cells):
        for j in range(cells):
            cx, cy = -2 + (i + 0.5) * h, -2 + (j + 0.5) * h
            if (cx - centre[0]) ** 2 + (cy - centre[1]) ** 2 < hole_radius ** 2:
                continue
            a, b, c, d = index[i, j], index[i + 1, j], index[i + 1, j + 1], index[i, j + 1]
            faces += [(a, b, c), (a, c, d)]
    used = sorted({v for f in faces for v in f})
    renumber = {v: k for k, v in enumerate(used)}
    positions = [tuple(scale * c for c in vertices[v]) for v in used]
    faces = [tuple(renumber[v] for v in f) for f in faces]
    if kind == "cylinder":
        obstacle = {"type": "cylinder", "center": [0, 0, 0], "radius": scale * radius,
                    "height": 6 * scale, "axis": [0, 1, 0]}
    else:
        obstacle = {"type": "sphere", "center": [0, 0, 0], "radius": scale * radius}
    floor = {"type": "plane", "point": [0, 0, -1.5 * scale], "normal": [0, 0, 1]}
    return positions, faces, [obstacle, floor], scale * h


def signed_distance(o, p):
    if o["type"] == "sphere":
        return math.dist(p, o["center"]) - o["radius"]
    if o["type"] == "plane":
        return sum((p[i] - o["point"][i]) * o["normal"][i] for i in range(3))
    a, c = o["axis"], o["center"]
    t = sum((p[i] - c[i]) * a[i] for i in range(3))
    t = max(-o["height"] / 2, min(o["height"] / 2, t))
    return math.dist(p, [c[i] + t * a[i] for i in range(3)]) - o["radius"]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("foldfill")
    parser.add_argument("out")
    parser.add_argument("--cells", type=int, default=140)
    parser.add_argument("--hole-radius", type=float, default=0.7)
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    for kind in ("cylinder", "sphere"):
        for scale in (1, 1000):
            name = f"{kind}_{scale}"
            positions, faces, obstacles, cell = sheet(kind, args.cells, scale, args.hole_radius)
            mesh = os.path.join(args.out, name + ".obj")
            with open(mesh, "w") as f:
                for p in positions:
                    f.write("v %.17g %.17g %.17g\n" % p)
                for t in faces:
                    f.write("f %d %d %d\n" % tuple(v + 1 for v in t))
            obstacle_file = os.path.join(args.out, name + ".json")
            with open(obstacle_file, "w") as f:
                json.dump({"obstacles": obstacles}, f)
            output = os.path.join(args.out, name + "_filled.obj")
            report_file = os.path.join(args.out, name + ".report.json")
            seconds = []
            for _ in range(args.runs):
                subprocess.run([args.foldfill, "fill", mesh, "--obstacles", obstacle_file,
                                "-o", output, "--report", report_file, "--quiet"],
                               check=True, env=env)
                with open(report_file) as f:
                    report = json.load(f)["holes"][0]
                seconds.append(report["seconds"]["total"])
            with open(output) as f:
                new = [tuple(map(float, line.split()[1:4])) for line in f
                       if line.startswith("v ")][len(positions):]
            least = min(signed_distance(o, p) for p in new for o in obstacles) / cell
            print(f"{name}: {len(new)} new vertices, least distance to the obstacles "
                  f"{least:.3f} cells, crossings {report['crossings']}, start {report['start']}, "
                  f"{report['iterations']} iterations, fill {statistics.median(seconds):.3f} s")


if __name__ == "__main__":
    main()
