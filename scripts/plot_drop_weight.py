#!/usr/bin/env python3
"""Charts of a damaged drop-weight run beside the elastic one: the tup's contact force
against time and against the tup's displacement, with the first load drop and the peak
marked, and the damage energy against time. Prints the figures the charts show.

usage: plot_drop_weight.py DAMAGED_DIR ELASTIC_DIR OUT_PREFIX

DAMAGED_DIR and ELASTIC_DIR are the output folders of `impact run
scenes/drop_weight_d7136.toml` and `impact run scenes/drop_weight_d7136_elastic.toml`;
the charts are OUT_PREFIX_force_time.png and OUT_PREFIX_force_displacement.png. Needs
matplotlib (`pip install matplotlib`).
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MASS = 5.5e-3  # tonne
V0 = 3303.0  # mm/s


def history(folder):
    rows = list(csv.DictReader(open(os.path.join(folder, "history.csv"))))
    col = lambda c: [float(r[c]) for r in rows] if c in rows[0] else None
    return {
        "t": [1e3 * x for x in col("time")],
        "f": [1e-3 * x for x in col("impact.normal_force")],
        "u": [-x for x in col("tup.uz")],
        "v": col("tup.vz"),
        "damage": col("damage_energy"),
        "energy": col("total_energy"),
    }


def first_drop(h, fall=0.1, onset=1.0):
    """The first row where the force falls `fall` below its running maximum, counted once
    the force has reached `onset` kN (the contact's first rows ring about a few newtons):
    (t, f) of that maximum."""
    peak, at = 0.0, 0
    for i, f in enumerate(h["f"]):
        if f > peak:
            peak, at = f, i
        elif peak >= onset and f < (1.0 - fall) * peak:
            return h["t"][at], peak
    return None


def figures(h, folder):
    f, t = h["f"], h["t"]
    i = max(range(len(f)), key=f.__getitem__)
    touching = [k for k, x in enumerate(f) if x > 0.0]
    contact = t[touching[-1]] - t[touching[0]] if touching else 0.0
    rebound = 0.5 * MASS * h["v"][-1] ** 2 * (1.0 if h["v"][-1] > 0 else -1.0)
    s = json.load(open(os.path.join(folder, "summary.json")))
    e = h["energy"]
    return {
        "peak_kN": f[i],
        "peak_ms": t[i],
        "first_drop": first_drop(h),
        "contact_ms": contact,
        "rebound_J": 1e-3 * rebound,
        "absorbed_J": 30.0 - 1e-3 * rebound,
        "damage_J": 1e-3 * (h["damage"][-1] if h["damage"] else 0.0),
        "balance": (max(e) - min(e)) / e[0],
        "projected_mm2": (s.get("delamination") or {}).get("projected_area"),
        "status": s["status"],
        "wall_s": s["wall_seconds"],
    }


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__)
    damaged, elastic, out = history(argv[1]), history(argv[2]), argv[3]
    for name, h, folder in (("damaged", damaged, argv[1]), ("elastic", elastic, argv[2])):
        print(name, figures(h, folder))
    drop = first_drop(damaged)
    def touching(h, x):
        """The rows up to the contact's end (against displacement: the tup flies off)."""
        end = max(k for k, f in enumerate(h["f"]) if f > 0.0) + 1 if x == "u" else len(h["f"])
        return h[x][:end], h["f"][:end]

    for x, name in (("t", "time"), ("u", "displacement")):
        fig, ax = plt.subplots(figsize=(7.2, 4.0), dpi=100)
        ax.plot(*touching(elastic, x), color="0.6", label="elastic coupon")
        ax.plot(*touching(damaged, x), color="C3", label="ply damage and delamination")
        if drop:
            k = damaged["t"].index(drop[0])
            ax.plot([damaged[x][k]], [drop[1]], "ko", ms=5)
            ax.annotate(
                f"first load drop {drop[1]:.2f} kN",
                (damaged[x][k], drop[1]),
                textcoords="offset points",
                xytext=(8, -14),
            )
        ax.set_xlabel("time (ms)" if x == "t" else "tup displacement (mm)")
        ax.set_ylabel("contact force (kN)")
        ax.set_title("ASTM D7136, 30 J on [45/0/-45/90]3s IM7/8552")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right")
        fig.tight_layout()
        path = f"{out}_force_{'time' if x == 't' else 'displacement'}.png"
        fig.savefig(path)
        print("wrote", path)


if __name__ == "__main__":
    main(sys.argv)
