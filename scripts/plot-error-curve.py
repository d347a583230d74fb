#!/usr/bin/env python3
"""Plots radiosity error curves (bench/radiosity_error_curve output) as an SVG: solve seconds
(log scale) against the median relative error of the total irradiance (log scale), one line per
series. A series starts at a line "=== NAME"; its rows are the bench's table rows. Series whose
name holds "reference:" take their points from the line itself, "reference: NAME s1:e1 s2:e2"
(seconds:median%), for published figures. No dependencies beyond Python 3.

Usage: plot-error-curve.py CURVES.txt OUT.svg [TITLE]
"""

import math
import sys

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f"]


def read_series(path):
    series = []
    for line in open(path, encoding="utf-8"):
        line = line.strip()
        if line.startswith("=== "):
            name = line[4:]
            points = []
            if name.startswith("reference:"):
                parts = name.split()
                name = " ".join(p for p in parts[1:] if ":" not in p)
                for p in parts[1:]:
                    if ":" in p:
                        seconds, median = p.split(":")
                        points.append((float(seconds), float(median)))
            series.append((name, points))
            continue
        fields = line.split()
        if series and len(fields) >= 7 and fields[0][0].isdigit() and fields[5].endswith("%"):
            series[-1][1].append((float(fields[2]), float(fields[5].rstrip("%"))))
    return [(name, points) for name, points in series if points]


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    series = read_series(sys.argv[1])
    title = sys.argv[3] if len(sys.argv) > 3 else "radiosity: solve time against median error"
    width, height, left, right, top, bottom = 720, 440, 70, 230, 40, 50
    xs = [s for _, pts in series for s, _ in pts]
    ys = [e for _, pts in series for _, e in pts]
    x0, x1 = math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs)))
    y0, y1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))

    def px(seconds):
        return left + (math.log10(seconds) - x0) / (x1 - x0) * (width - left - right)

    def py(error):
        return height - bottom - (math.log10(error) - y0) / (y1 - y0) * (height - top - bottom)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'font-family="sans-serif" font-size="12">',
           f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<text x="{left}" y="24" font-size="14">{title}</text>']
    for k in range(x0, x1 + 1):
        x = px(10 ** k)
        out.append(f'<line x1="{x:.1f}" y1="{top}" x2="{x:.1f}" y2="{height - bottom}" '
                   'stroke="#ddd"/>')
        out.append(f'<text x="{x:.1f}" y="{height - bottom + 16}" text-anchor="middle">'
                   f'{10 ** k:g} s</text>')
    for k in range(y0, y1 + 1):
        y = py(10 ** k)
        out.append(f'<line x1="{left}" y1="{y:.1f}" x2="{width - right}" y2="{y:.1f}" '
                   'stroke="#ddd"/>')
        out.append(f'<text x="{left - 6}" y="{y + 4:.1f}" text-anchor="end">{10 ** k:g}%</text>')
    out.append(f'<text x="{(left + width - right) / 2}" y="{height - 12}" '
               'text-anchor="middle">solve time (one core unless named)</text>')
    out.append(f'<text x="16" y="{(top + height - bottom) / 2}" text-anchor="middle" '
               f'transform="rotate(-90 16 {(top + height - bottom) / 2})">median error</text>')
    for i, (name, points) in enumerate(series):
        colour = COLOURS[i % len(COLOURS)]
        path = " ".join(f"{px(s):.1f},{py(e):.1f}" for s, e in sorted(points))
        out.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for s, e in points:
            out.append(f'<circle cx="{px(s):.1f}" cy="{py(e):.1f}" r="3" fill="{colour}"/>')
        y = top + 10 + 18 * i
        out.append(f'<line x1="{width - right + 12}" y1="{y}" x2="{width - right + 32}" y2="{y}" '
                   f'stroke="{colour}" stroke-width="2"/>')
        out.append(f'<text x="{width - right + 38}" y="{y + 4}">{name}</text>')
    out.append("</svg>")
    with open(sys.argv[2], "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
