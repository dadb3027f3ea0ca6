#!/usr/bin/env python3
"""Small folded sheets with one hole each, as OBJ files, for the tests of the
Python module and of the batch recipe (standard library only).

    make_sheets.py OUTDIR COUNT     writes OUTDIR/sheet_00.obj ... (COUNT files)

Sheet k is a grid of nx * ny vertices over [0, width] x [0, height], folded
across x (z = amplitude * sin(2 pi folds x / width)), with the faces whose
centroid lies within `radius` of a point removed: one hole inside the sheet.
Its size, folds, amplitude and hole change with k.
"""

import math
import os
import sys


def folded_sheet(k=0, nx=17, ny=15):
    """(vertices, faces) of sheet k: lists of [x, y, z] and of [a, b, c]."""
    width, height = 1.6, 1.4
    folds = 1 + k % 3
    amplitude = 0.1 + 0.02 * (k % 4)
    vertices = []
    for j in range(ny):
        for i in range(nx):
            x = width * i / (nx - 1)
            y = height * j / (ny - 1)
            vertices.append([x, y, amplitude * math.sin(2 * math.pi * folds * x / width)])
    center = (0.55 + 0.5 * ((k * 7) % 5) / 4, 0.5 + 0.4 * ((k * 3) % 4) / 3)
    radius = 0.2 + 0.03 * (k % 3)
    faces = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            a, b = j * nx + i, j * nx + i + 1
            c, d = a + nx, b + nx
            for face in ([a, b, d], [a, d, c]):
                cx = sum(vertices[v][0] for v in face) / 3
                cy = sum(vertices[v][1] for v in face) / 3
                if math.hypot(cx - center[0], cy - center[1]) > radius:
                    faces.append(face)
    return vertices, faces


def obj_text(vertices, faces):
    lines = ["v {!r} {!r} {!r}".format(*v) for v in vertices]
    lines += ["f {} {} {}".format(*(v + 1 for v in f)) for f in faces]
    return "\n".join(lines) + "\n"


def main(argv):
    if len(argv) != 3:
        sys.exit("usage: make_sheets.py OUTDIR COUNT")
    out_dir, count = argv[1], int(argv[2])
    os.makedirs(out_dir, exist_ok=True)
    for k in range(count):
        with open(os.path.join(out_dir, "sheet_{:02d}.obj".format(k)), "w") as out:
            out.write(obj_text(*folded_sheet(k)))


if __name__ == "__main__":
    main(sys.argv)
