"""Checks a decomposed run's VTU frames against a single process's, value for value.

usage: compare_pieces.py SERIAL_DIR RANKS_DIR STEM

For every frame `STEM_NNNNNN.vtu` of SERIAL_DIR, RANKS_DIR must hold `STEM_NNNNNN.pvtu`
and its pieces. Every point of a piece is a node of the serial frame (matched by its
reference coordinates) with the same displacement, velocity, contact pressure and gap;
every cell of a piece is a cell of the serial frame (matched by its corners) with the same
stress, von Mises stress, body and material; the pieces cover every node and hold every
cell once. Exact equality: the decomposed run is the same bits. Exits 1 with the first
difference.
"""
import re
import sys
from pathlib import Path

import meshio
import numpy as np


def same(a, b):
    return np.array_equal(a, b, equal_nan=True)


def check_frame(serial_path, pvtu_path):
    s = meshio.read(serial_path)
    if not same(s.point_data["node"], np.arange(len(s.points))):
        sys.exit(f"{serial_path}: its node array is not 0..n")
    cell_of = {}
    for i, c in enumerate([row for block in s.cells for row in block.data]):
        cell_of[tuple(sorted(c))] = i
    serial_cell_data = {k: np.concatenate(v) for k, v in s.cell_data.items()}
    sources = re.findall(r'Source="([^"]+)"', pvtu_path.read_text())
    if not sources:
        sys.exit(f"{pvtu_path}: no pieces")
    nodes_seen = np.zeros(len(s.points), dtype=bool)
    cells_seen = np.zeros(len(cell_of), dtype=int)
    for src in sources:
        p = meshio.read(pvtu_path.parent / src)
        nodes = p.point_data["node"].astype(int)
        if not same(p.points, s.points[nodes]):
            sys.exit(f"{src}: points differ from {serial_path.name}")
        nodes_seen[nodes] = True
        for name, values in p.point_data.items():
            if not same(values, s.point_data[name][nodes]):
                sys.exit(f"{src}: point data {name} differs from {serial_path.name}")
        piece_cells = [row for block in p.cells for row in block.data]
        index = np.array([cell_of[tuple(sorted(nodes[c]))] for c in piece_cells])
        cells_seen[index] += 1
        for name, values in p.cell_data.items():
            if not same(np.concatenate(values), serial_cell_data[name][index]):
                sys.exit(f"{src}: cell data {name} differs from {serial_path.name}")
    if not nodes_seen.all():
        sys.exit(f"{pvtu_path.name}: {int((~nodes_seen).sum())} nodes in no piece")
    if not (cells_seen == 1).all():
        sys.exit(f"{pvtu_path.name}: cells not held exactly once")


def main():
    serial, ranks, stem = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
    frames = sorted(serial.glob(f"{stem}_[0-9][0-9][0-9][0-9][0-9][0-9].vtu"))
    if not frames:
        sys.exit(f"{serial}: no frames")
    for f in frames:
        check_frame(f, ranks / (f.stem + ".pvtu"))
    print(f"{len(frames)} frames: every piece equals the single-process frame")


main()
