#!/usr/bin/env python3
"""Plots columns of a history.csv against time as a small standalone SVG (no dependencies).

usage: plot_history.py HISTORY.csv OUT.svg COLUMN [COLUMN ...] [--title T] [--mark T=LABEL ...]
"""
import csv
import sys


def main(argv):
    args, title, marks = [], "", []
    it = iter(argv[1:])
    for a in it:
        if a == "--title":
            title = next(it)
        elif a == "--mark":
            t, label = next(it).split("=", 1)
            marks.append((float(t), label))
        else:
            args.append(a)
    if len(args) < 3:
        sys.exit(__doc__)
    path, out, cols = args[0], args[1], args[2:]
    rows = list(csv.DictReader(open(path)))
    for c in cols:
        if c not in rows[0]:
            sys.exit(f"{path}: no column {c!r}")
    t = [float(r["time"]) for r in rows]
    ys = {c: [float(r[c]) for r in rows] for c in cols}
    w, h, m = 720, 360, 60
    lo = min(min(v) for v in ys.values())
    hi = max(max(v) for v in ys.values())
    if hi == lo:
        hi = lo + 1.0
    t0, t1 = t[0], t[-1]
    sx = lambda x: m + (x - t0) / (t1 - t0) * (w - 2 * m)
    sy = lambda y: h - m - (y - lo) / (hi - lo) * (h - 2 * m)
    colors = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
    s = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
         f'<rect width="{w}" height="{h}" fill="white"/>',
         f'<text x="{w/2}" y="20" text-anchor="middle" font-size="14">{title}</text>',
         f'<line x1="{m}" y1="{h-m}" x2="{w-m}" y2="{h-m}" stroke="black"/>',
         f'<line x1="{m}" y1="{m}" x2="{m}" y2="{h-m}" stroke="black"/>']
    for k in range(6):
        x = t0 + k * (t1 - t0) / 5
        s.append(f'<text x="{sx(x):.1f}" y="{h-m+16}" text-anchor="middle">{x:.3g}</text>')
        y = lo + k * (hi - lo) / 5
        s.append(f'<text x="{m-6}" y="{sy(y)+4:.1f}" text-anchor="end">{y:.3g}</text>')
        s.append(f'<line x1="{m}" y1="{sy(y):.1f}" x2="{w-m}" y2="{sy(y):.1f}" stroke="#ddd"/>')
    if lo < 0 < hi:
        s.append(f'<line x1="{m}" y1="{sy(0):.1f}" x2="{w-m}" y2="{sy(0):.1f}" stroke="#888"/>')
    s.append(f'<text x="{w/2}" y="{h-12}" text-anchor="middle">time</text>')
    for j, (tm, label) in enumerate(marks):
        s.append(f'<line x1="{sx(tm):.1f}" y1="{m}" x2="{sx(tm):.1f}" y2="{h-m}" stroke="#999" stroke-dasharray="4 3"/>')
        s.append(f'<text x="{sx(tm)+3:.1f}" y="{m+12+14*j}" fill="#555">{label}</text>')
    for i, c in enumerate(cols):
        pts = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in zip(t, ys[c]))
        col = colors[i % len(colors)]
        s.append(f'<polyline fill="none" stroke="{col}" stroke-width="1.8" points="{pts}"/>')
        s.append(f'<text x="{w-m+4}" y="{m+16*i+4}" fill="{col}">{c}</text>')
    s.append("</svg>")
    open(out, "w").write("\n".join(s) + "\n")


if __name__ == "__main__":
    main(sys.argv)
