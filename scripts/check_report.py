#!/usr/bin/env python3
"""Judge a headless-Chromium rendering of an entrynav HTML report (scripts/check_report.sh).

usage: check_report.py SCREENSHOT.png DOM.html CHROMIUM_STDERR SECTION...

Fails (exit 1) when the console logged anything (the report has no scripts, so any console
message is an error), the page references the network, the dumped DOM lacks a section or inline
SVG or has almost no text, or the screenshot is blank (almost every pixel white). Standard
library only: the PNG is decoded here (8-bit RGB/RGBA, non-interlaced, as Chromium writes it).
"""
import re
import struct
import sys
import zlib


def png_pixels(path):
    """(width, height, channels, rows) of an 8-bit non-interlaced PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, head = 8, b"", None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos : pos + 4])
        kind, body = data[pos + 4 : pos + 8], data[pos + 8 : pos + 8 + n]
        if kind == b"IHDR":
            head = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    w, h, depth, color, _, _, interlace = head
    channels = {2: 3, 6: 4}.get(color)
    if depth != 8 or channels is None or interlace:
        raise ValueError(f"{path}: unsupported PNG (depth {depth}, color {color})")
    raw = zlib.decompress(idat)
    stride = w * channels
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1 : (y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = prev[i]
            c = prev[i - channels] if i >= channels else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        rows.append(line)
        prev = line
    return w, h, channels, rows


def ink_fraction(path):
    """Fraction of pixels that are not (near) white, sampled every 4th pixel and row."""
    w, h, ch, rows = png_pixels(path)
    ink = total = 0
    for y in range(0, h, 4):
        row = rows[y]
        for x in range(0, w, 4):
            r, g, b = row[x * ch], row[x * ch + 1], row[x * ch + 2]
            total += 1
            ink += (r + g + b) < 3 * 235
    return ink / max(total, 1)


def main():
    png, dom_path, log_path, *sections = sys.argv[1:]
    problems = []
    log = open(log_path, encoding="utf-8", errors="replace").read()
    console = [l for l in log.splitlines() if ":CONSOLE" in l]
    if console:
        problems.append("console messages:\n  " + "\n  ".join(console))
    dom = open(dom_path, encoding="utf-8", errors="replace").read()
    for s in sections:
        if f'id="{s}"' not in dom:
            problems.append(f"section {s} missing from the rendered DOM")
    if dom.count("<svg") < 2:
        problems.append(f"only {dom.count('<svg')} inline SVG figures")
    for m in re.finditer(r'(?:src|href)\s*=\s*["\']?\s*(https?:)?//', dom):
        problems.append(f"network reference: {m.group(0)}")
    text = re.sub(r"<[^>]+>", " ", re.sub(r"<svg.*?</svg>", " ", dom, flags=re.S))
    words = len(text.split())
    if words < 200:
        problems.append(f"only {words} words of text outside the figures")
    # Phrases the caller expects on the page (CHECK_REPORT_EXPECT, separated by "|"), e.g. the
    # recommendation line and a diverged filter's verdict.
    import os

    for phrase in filter(None, os.environ.get("CHECK_REPORT_EXPECT", "").split("|")):
        if phrase not in " ".join(text.split()):
            problems.append(f"the rendered page lacks '{phrase}'")
    ink = ink_fraction(png)
    if ink < 0.02:
        problems.append(f"screenshot is blank ({100 * ink:.2f} % non-white pixels)")
    if problems:
        print("check_report: FAILED\n" + "\n".join(problems), file=sys.stderr)
        return 1
    print(f"check_report: ok ({len(sections)} sections, {dom.count('<svg')} figures, "
          f"{words} words, {100 * ink:.1f} % ink)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
