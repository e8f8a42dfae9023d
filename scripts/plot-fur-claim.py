#!/usr/bin/env python3
"""Quality against time for steep parallax fur and shells (issue 27, docs/fur.md).

Reads a table of measured points, one per line: scene, family, count, frame ms, PSNR dB (the
figures of docs/fur.md "Whole frames of the scenes", from bench/bench_fur.cpp and
tests/frames/fur_convergence_test.cpp), and writes an SVG: frame time (log axis) against PSNR
versus `exact`, one line per scene and family, each point labelled with its count.

    scripts/plot-fur-claim.py docs/fur_claim_points.txt docs/fur_claim.svg
"""
import math
import sys

W, H, L, R, T, B = 620, 380, 64, 170, 24, 50
COLOURS = {"steep_parallax": "#1f77b4", "shells": "#d62728"}
DASH = {"fur": "", "grass": "6,4"}


def read_points(path):
    points = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            scene, family, count, ms, psnr = line.split()
            points.append((scene, family, int(count), float(ms), float(psnr)))
    return points


def svg(points):
    x0 = math.floor(math.log10(min(p[3] for p in points)) * 4) / 4
    x1 = math.ceil(math.log10(max(p[3] for p in points)) * 4) / 4
    y0 = math.floor(min(p[4] for p in points)) - 1
    y1 = math.ceil(max(p[4] for p in points)) + 1

    def X(ms):
        return L + (math.log10(ms) - x0) / (x1 - x0) * (W - L - R)

    def Y(db):
        return T + (y1 - db) / (y1 - y0) * (H - T - B)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
           'font-family="sans-serif" font-size="11">',
           f'<rect x="0" y="0" width="{W}" height="{H}" fill="white"/>']
    for ms in (100, 200, 500, 1000, 2000, 5000):
        if x0 <= math.log10(ms) <= x1:
            out.append(f'<line x1="{X(ms):.1f}" y1="{T}" x2="{X(ms):.1f}" y2="{H - B}" '
                       'stroke="#ddd"/>')
            out.append(f'<text x="{X(ms):.1f}" y="{H - B + 14}" text-anchor="middle">{ms}</text>')
    for db in range(int(y0), int(y1) + 1, 2):
        out.append(f'<line x1="{L}" y1="{Y(db):.1f}" x2="{W - R}" y2="{Y(db):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{L - 6}" y="{Y(db) + 4:.1f}" text-anchor="end">{db}</text>')
    out.append(f'<text x="{(L + W - R) / 2}" y="{H - 12}" text-anchor="middle">'
               'frame time at 1024x768, 2 threads (ms, log)</text>')
    out.append(f'<text x="16" y="{(T + H - B) / 2}" text-anchor="middle" '
               f'transform="rotate(-90 16 {(T + H - B) / 2})">PSNR against exact (dB)</text>')
    legend_y = T + 10
    for scene in ("fur", "grass"):
        for family in ("steep_parallax", "shells"):
            pts = sorted((p for p in points if p[0] == scene and p[1] == family),
                         key=lambda p: p[2])
            if not pts:
                continue
            path = " ".join(f"{X(p[3]):.1f},{Y(p[4]):.1f}" for p in pts)
            out.append(f'<polyline points="{path}" fill="none" stroke="{COLOURS[family]}" '
                       f'stroke-width="1.5" stroke-dasharray="{DASH[scene]}"/>')
            for p in pts:
                out.append(f'<circle cx="{X(p[3]):.1f}" cy="{Y(p[4]):.1f}" r="3" '
                           f'fill="{COLOURS[family]}"/>')
                out.append(f'<text x="{X(p[3]) + 4:.1f}" y="{Y(p[4]) - 4:.1f}" '
                           f'font-size="9">{p[2]}</text>')
            lx = W - R + 14
            out.append(f'<line x1="{lx}" y1="{legend_y}" x2="{lx + 24}" y2="{legend_y}" '
                       f'stroke="{COLOURS[family]}" stroke-width="1.5" '
                       f'stroke-dasharray="{DASH[scene]}"/>')
            out.append(f'<text x="{lx + 30}" y="{legend_y + 4}">{scene}: {family}</text>')
            legend_y += 18
    out.append("</svg>")
    return "\n".join(out) + "\n"


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot-fur-claim.py POINTS.txt OUT.svg")
    points = read_points(sys.argv[1])
    if not points:
        sys.exit(f"{sys.argv[1]}: no points")
    with open(sys.argv[2], "w") as f:
        f.write(svg(points))


if __name__ == "__main__":
    main()
