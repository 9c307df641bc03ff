"""Writes graded_block.inp: a quarter of an elastic block under a point of contact at the
origin, [0, W] x [0, W] x [-W, 0], as C3D8 elements graded towards the origin: cells of H0
out to U along each axis, then each cell GROWTH times the one before until the side W is
reached. Node sets SYMMETRY_X (x = 0), SYMMETRY_Y (y = 0) and BASE (z = -W); the surface
TOP (z = 0). Run: python3 graded_block.py"""

H0, U, GROWTH, W = 0.025, 0.3, 1.3, 12.0


def stations():
    """The cell boundaries from 0 to W."""
    s = [0.0]
    while s[-1] < U - 1e-12:
        s.append(s[-1] + H0)
    h = H0
    while s[-1] < W - 1e-12:
        h *= GROWTH
        s.append(min(s[-1] + h, W))
    if W - s[-2] < 0.5 * (s[-2] - s[-3]):  # no sliver cell at the far side
        s.pop(-2)
    return s


X = stations()
Z = [-x for x in reversed(X)]  # from the base up to the top at 0
N = len(X) - 1
lines = [f"** quarter block, {N} x {N} x {N} C3D8 graded to the origin, written by graded_block.py",
         "*HEADING", "graded quarter block"]
nid = lambda i, j, k: 1 + i + (N + 1) * (j + (N + 1) * k)
lines.append("*NODE, NSET=ALLNODES")
for k in range(N + 1):
    for j in range(N + 1):
        for i in range(N + 1):
            lines.append(f"{nid(i, j, k)}, {X[i]:.9g}, {X[j]:.9g}, {Z[k]:.9g}")
lines.append("*ELEMENT, TYPE=C3D8, ELSET=BLOCK")
eid = lambda i, j, k: 1 + i + N * (j + N * k)
for k in range(N):
    for j in range(N):
        for i in range(N):
            c = [nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k),
                 nid(i, j, k + 1), nid(i + 1, j, k + 1), nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1)]
            lines.append(f"{eid(i, j, k)}, " + ", ".join(map(str, c[:4])) + ",")
            lines.append("    " + ", ".join(map(str, c[4:])))
lines.append("*ELSET, ELSET=TOP_LAYER, GENERATE")
lines.append(f"{N * N * (N - 1) + 1}, {N * N * N}, 1")


def node_set(name, ids):
    lines.append(f"*NSET, NSET={name}")
    for s in range(0, len(ids), 16):
        lines.append(", ".join(map(str, ids[s:s + 16])))


node_set("SYMMETRY_X", [nid(0, j, k) for k in range(N + 1) for j in range(N + 1)])
node_set("SYMMETRY_Y", [nid(i, 0, k) for k in range(N + 1) for i in range(N + 1)])
node_set("BASE", [nid(i, j, 0) for j in range(N + 1) for i in range(N + 1)])
lines.append("*SURFACE, NAME=TOP, TYPE=ELEMENT")
lines.append("TOP_LAYER, S2")
open("graded_block.inp", "w").write("\n".join(lines) + "\n")
