"""Writes block_hex.inp: the unit cube [-0.5, 0.5] x [-0.5, 0.5] x [0, 1] as 8 x 8 x 8 C3D8
elements (the same block as block_tet.geo), with node sets and element-side surfaces as an
Abaqus/CalculiX deck. Run: python3 block_hex.py"""

N = 8
lines = ["** unit cube, 8 x 8 x 8 C3D8, written by block_hex.py", "*HEADING", "unit cube hex8"]
nid = lambda i, j, k: 1 + i + (N + 1) * (j + (N + 1) * k)
lines.append("*NODE, NSET=ALLNODES")
for k in range(N + 1):
    for j in range(N + 1):
        for i in range(N + 1):
            lines.append(f"{nid(i, j, k)}, {i / N - 0.5:.6f}, {j / N - 0.5:.6f}, {k / N:.6f}")
lines.append("*ELEMENT, TYPE=C3D8, ELSET=BLOCK")
eid = lambda i, j, k: 1 + i + N * (j + N * k)
for k in range(N):
    for j in range(N):
        for i in range(N):
            c = [nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k),
                 nid(i, j, k + 1), nid(i + 1, j, k + 1), nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1)]
            # eight nodes over two lines, as CalculiX writes long element lines
            lines.append(f"{eid(i, j, k)}, " + ", ".join(map(str, c[:4])) + ",")
            lines.append("    " + ", ".join(map(str, c[4:])))
lines.append("*ELSET, ELSET=BOTTOM_LAYER, GENERATE")
lines.append(f"1, {N * N}, 1")
lines.append("*ELSET, ELSET=TOP_LAYER, GENERATE")
lines.append(f"{N * N * (N - 1) + 1}, {N * N * N}, 1")
lines.append("*NSET, NSET=BASE")
base = [nid(i, j, 0) for j in range(N + 1) for i in range(N + 1)]
for s in range(0, len(base), 16):
    lines.append(", ".join(map(str, base[s:s + 16])))
lines.append("*SURFACE, NAME=BOTTOM, TYPE=ELEMENT")
lines.append("BOTTOM_LAYER, S1")
lines.append("*SURFACE, NAME=TOP, TYPE=ELEMENT")
lines.append("TOP_LAYER, S2")
lines.append("*MATERIAL, NAME=ELASTIC")
lines.append("*ELASTIC")
lines.append("100.0, 0.3")
lines.append("*DENSITY")
lines.append("0.01")
open("block_hex.inp", "w").write("\n".join(lines) + "\n")
