#!/usr/bin/env python3
"""Independent check of a run's VTU frames with meshio (pip install meshio).

    check_vtu.py RUN_DIR STEM [NAME=NODE ...]

Reads RUN_DIR/STEM.pvd and every frame it lists, and RUN_DIR/history.csv. For each probe
NAME=NODE (the probe's node number), the displacement meshio reads at that node must equal
the history's NAME.ux/uy/uz in the row of the frame's time (to 1e-12 relative to the
largest displacement). Also checks: every frame has the same points and cells (hexahedra
and/or tetrahedra), the
arrays the docs promise are there with the right shapes, and von_mises agrees with the
stress components. Prints one line per frame; exits 1 on the first failure.
"""
import csv
import math
import sys
import xml.etree.ElementTree as ET

import meshio


def fail(msg):
    print(f"check_vtu: FAIL: {msg}")
    sys.exit(1)


def main():
    run_dir, stem = sys.argv[1], sys.argv[2]
    probes = [(a.split("=")[0], int(a.split("=")[1])) for a in sys.argv[3:]]
    pvd = ET.parse(f"{run_dir}/{stem}.pvd").getroot()
    frames = [(float(d.get("timestep")), d.get("file")) for d in pvd.iter("DataSet")]
    if not frames:
        fail("no frames in the collection")
    with open(f"{run_dir}/history.csv") as f:
        rows = list(csv.DictReader(f))
    times = [float(r["time"]) for r in rows]
    scale = max(
        abs(float(r[f"{name}.u{c}"])) for r in rows for name, _ in probes for c in "xyz"
    ) if probes else 1.0
    scale = max(scale, 1e-300)
    first = None
    worst = 0.0
    for t, name in frames:
        mesh = meshio.read(f"{run_dir}/{name}")
        kinds = [k for k in ("hexahedron", "tetra") if k in mesh.cells_dict]
        if not kinds or len(kinds) != len(mesh.cells_dict):
            fail(f"{name}: cells {list(mesh.cells_dict)}, expected hexahedra and/or tetrahedra")
        shape = (mesh.points.shape, [(k, mesh.cells_dict[k].shape) for k in kinds])
        if first is None:
            first = shape
        elif shape != first:
            fail(f"{name}: mesh changed")
        n = mesh.points.shape[0]
        for key, shape in [("displacement", (n, 3)), ("velocity", (n, 3)),
                           ("contact_pressure", (n,)), ("contact_gap", (n,))]:
            if key not in mesh.point_data or mesh.point_data[key].shape != shape:
                fail(f"{name}: point data {key} missing or not {shape}")
        counts = []
        for kind in kinds:
            m = mesh.cells_dict[kind].shape[0]
            counts.append(f"{m} {kind}")
            stress = mesh.cell_data_dict.get("stress", {}).get(kind)
            vm = mesh.cell_data_dict.get("von_mises", {}).get(kind)
            if stress is None or stress.shape != (m, 6) or vm is None or vm.shape != (m,):
                fail(f"{name}: cell data stress (m, 6) and von_mises (m,) expected on {kind}")
            for s, v in zip(stress, vm):
                d = (s[0] - s[1]) ** 2 + (s[1] - s[2]) ** 2 + (s[2] - s[0]) ** 2
                ref = math.sqrt(0.5 * d + 3 * (s[3] ** 2 + s[4] ** 2 + s[5] ** 2))
                if abs(ref - v) > 1e-9 * max(1.0, abs(ref)):
                    fail(f"{name}: von_mises {v} against {ref} from the components")
        row = min(range(len(times)), key=lambda i: abs(times[i] - t))
        if abs(times[row] - t) > 1e-12 * max(1.0, abs(t)):
            fail(f"{name}: no history row at t = {t}")
        for pname, node in probes:
            for a, c in enumerate("xyz"):
                h = float(rows[row][f"{pname}.u{c}"])
                d = abs(mesh.point_data["displacement"][node][a] - h) / scale
                worst = max(worst, d)
                if d > 1e-12:
                    fail(f"{name}: {pname}.u{c} {mesh.point_data['displacement'][node][a]} against history {h}")
        print(f"check_vtu: {name}: t = {t:.6e}, {n} points, {', '.join(counts)}, ok")
    print(f"check_vtu: {len(frames)} frames ok; worst probe difference {worst:.2e} of scale")


if __name__ == "__main__":
    main()
