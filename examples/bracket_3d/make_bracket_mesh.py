#!/usr/bin/python3
"""Writes bracket.msh, the Gmsh 4.1 ASCII mesh of examples/bracket_3d/bracket.yaml.

An L-shaped bracket of 8-node hexahedra (Gmsh type 5), in mm: a leg x in [0, 10], y in [0, 60]
and an arm x in [0, 60], y in [50, 60], both z in [0, 20], on a grid of 2.5 mm cubes (4 elements
through every thickness). Physical groups: volume "bracket" (two volume entities, the leg below
the arm and the arm), surfaces "base" (the face y = 0, quadrangles of type 3, normals outward)
and "tip" (the arm's end face x = 60), point "tip_center" (the node at (60, 55, 10)).
The file is what Gmsh writes for such a model (one node block, one element block per entity),
so the example needs no Gmsh; rerun this script to remake it:
    /usr/bin/python3 examples/bracket_3d/make_bracket_mesh.py
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from gmsh_writer import write_msh  # noqa: E402

H = 2.5                     # element size
NX, NY, NZ = 24, 24, 8      # grid cells over the bounding box 60 x 60 x 20
LEG_I, ARM_J = 4, 20        # leg: cells i < 4 (x < 10); arm: cells j >= 20 (y >= 50)


def in_leg(i, j):
    return i < LEG_I and j < ARM_J


def in_arm(i, j):
    return j >= ARM_J


def main():
    cells = {1: [], 2: []}  # volume entity -> cells (i, j, k)
    for k in range(NZ):
        for j in range(NY):
            for i in range(NX):
                if in_leg(i, j):
                    cells[1].append((i, j, k))
                elif in_arm(i, j):
                    cells[2].append((i, j, k))
    tags = {}  # grid point -> node tag, numbered in the order of first use

    def tag(p):
        if p not in tags:
            tags[p] = len(tags) + 1
        return tags[p]

    hexes = {}
    for entity, cs in cells.items():
        hexes[entity] = [[tag((i + di, j + dj, k + dk))
                          for dk in (0, 1) for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1))]
                         for i, j, k in cs]
    # Boundary quadrangles, counter-clockwise seen from outside (outward normal).
    base = [[tag((i, 0, k)), tag((i + 1, 0, k)), tag((i + 1, 0, k + 1)), tag((i, 0, k + 1))]
            for i, j, k in cells[1] if j == 0]
    tip = [[tag((NX, j, k)), tag((NX, j + 1, k)), tag((NX, j + 1, k + 1)), tag((NX, j, k + 1))]
           for i, j, k in cells[2] if i == NX - 1]
    center = tag((NX, ARM_J + (NY - ARM_J) // 2, NZ // 2))

    nodes = sorted(tags.items(), key=lambda item: item[1])
    blocks = [(3, 1, 5, hexes[1]), (3, 2, 5, hexes[2]), (2, 1, 3, base), (2, 2, 3, tip),
              (0, 1, 15, [[center]])]
    entities = ((1, 0, 2, 2), ["1 60 55 10 1 4", "1 0 0 0 10 0 20 1 2 0",
                               "2 60 50 0 60 60 20 1 3 0", "1 0 0 0 10 50 20 1 1 0",
                               "2 0 50 0 60 60 20 1 1 0"])
    coordinates = [f"{H * p[0]:g} {H * p[1]:g} {H * p[2]:g}" for p, _ in nodes]
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bracket.msh")
    write_msh(path, [(0, 4, "tip_center"), (2, 2, "base"), (2, 3, "tip"), (3, 1, "bracket")],
              entities, coordinates, blocks)
    print(f"wrote {path}: {len(nodes)} nodes, {len(hexes[1]) + len(hexes[2])} hexahedra, "
          f"{len(base)} + {len(tip)} boundary quadrangles")


if __name__ == "__main__":
    main()
