#!/usr/bin/env python3
"""Compare two output snapshots (scripts/snapshot_outputs.sh) file by file.

Usage: scripts/compare_outputs.py OLD_DIR NEW_DIR [--only PREFIX ...]

Equal means bit for bit, outside what measures the machine rather than the result:
- JSON: the keys `timing`, `provenance`, `wall_s`, `elapsed_s`, `search_s`, `seconds` and keys ending
  in `_wall_s` are dropped at any depth; every other value (floats included) must be equal.
- Text (standard output and error, HTML, Markdown, TOML comments): the snapshot folder's path, wall times (`12.34 s`, `(5.1 s wall)`,
  `in 0.123 s`, `µs per filter step`) and the tool version line are masked before comparing.
- Everything else (CSV, SVG, XML, TOML): byte for byte.
A file present on one side only is a difference. Exit code 0 when all equal, 1 otherwise.
"""

import json
import os
import re
import sys

DROP_KEYS = {"timing", "provenance", "wall_s", "elapsed_s", "search_s", "seconds", "generated_by",
             "solve_time_s", "filter_ns", "us_per_step"}
# Table columns (CSV, Markdown, HTML) that hold CPU time, matched on their header.
TIMING_HEADER = re.compile(r"µs|us_per_step|wall|solve_time")
# Files that are a plot of CPU time.
TIMING_FILES = re.compile(r"us_per_step")
TIME_PATTERNS = [
    (re.compile(r"\d+(\.\d+)?(e-?\d+)? ?(µs|us|ms|s)\b( wall| in all| per \w+)?"), "<time>"),
    (re.compile(r"\d+(\.\d+)?x faster"), "<speed-up>"),
    (re.compile(r"\(\d+×\)"), "(<speed-up>)"),
    (re.compile(r"(entrynav|version) \d+\.\d+\.\d+[^\s\"<]*"), "<version>"),
]
TEXT_SUFFIXES = (".stdout", ".stderr", ".html", ".md", ".txt")


def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if k not in DROP_KEYS and not k.endswith("_wall_s")}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v


def mask_columns(rows, split, join):
    """Blank the cells under a timing header in a table given as lines."""
    out, hide = [], set()
    for line in rows:
        cells = split(line)
        if cells is None:
            hide = set()
            out.append(line)
            continue
        if any(TIMING_HEADER.search(c) for c in cells):
            hide = {i for i, c in enumerate(cells) if TIMING_HEADER.search(c)}
        elif hide:
            cells = ["<timing>" if i in hide else c for i, c in enumerate(cells)]
            line = join(cells)
        out.append(line)
    return out


def md_cells(line):
    return line.split("|") if line.startswith("|") else None


def html_cells(line):
    return re.findall(r"<t[hd][^>]*>(.*?)</t[hd]>", line) if line.startswith("<tr>") else None


def mask(text):
    # A figure of CPU time inside a page.
    text = re.sub(r"<svg(?:(?!</svg>).)*µs(?:(?!</svg>).)*</svg>", "<timing-figure>", text, flags=re.S)
    for pat, rep in TIME_PATTERNS:
        text = pat.sub(rep, text)
    lines = text.splitlines()
    # A JSON block shown in a page: its timing entries and the command line (the binary's path).
    inside = False
    for i, line in enumerate(lines):
        if re.search(r"us_per_step|wall_s|command_line|git_commit", line):
            inside = line.rstrip().endswith(("{", "["))
            lines[i] = re.sub(r"[-\d.e]+", "<n>", line)
            if "git_commit" in line:
                lines[i] = "<commit>"
        elif inside:
            if line.strip() in ("}", "},", "]", "],"):
                inside = False
            else:
                lines[i] = "<machine-dependent>"
    lines = mask_columns(lines, md_cells, "|".join)
    lines = mask_columns(lines, html_cells, lambda c: "<tr>" + "".join(f"<td>{x}</td>" for x in c) + "</tr>")
    return "\n".join(lines)


def mask_csv(text):
    import csv
    import io
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        return text
    hide = {i for i, c in enumerate(rows[0]) if TIMING_HEADER.search(c)}
    return "\n".join(",".join("<timing>" if i in hide else c for i, c in enumerate(r)) for r in rows)


def first_difference(a, b, path="$"):
    if type(a) is not type(b):
        return f"{path}: {type(a).__name__} vs {type(b).__name__}"
    if isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{path}.{k}: only in {'new' if k in b else 'old'}"
            d = first_difference(a[k], b[k], f"{path}.{k}")
            if d:
                return d
        return None
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{path}: {len(a)} vs {len(b)} items"
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, f"{path}[{i}]")
            if d:
                return d
        return None
    if a != b and not (isinstance(a, float) and a != a and b != b):
        return f"{path}: {a!r} vs {b!r}"
    return None


def compare_file(old, new, roots=("", "")):
    if old.endswith(".json"):
        try:
            a, b = json.load(open(old)), json.load(open(new))
        except ValueError:
            pass
        else:
            # Paths inside the snapshot folders (`trade compare` names its inputs).
            a = json.loads(json.dumps(a).replace(roots[0], "<snapshot>"))
            b = json.loads(json.dumps(b).replace(roots[1], "<snapshot>"))
            return first_difference(strip(a), strip(b))
    ta, tb = open(old, "rb").read(), open(new, "rb").read()
    if ta == tb or TIMING_FILES.search(os.path.basename(old)):
        return None
    if old.endswith(".csv") and mask_csv(ta.decode()) == mask_csv(tb.decode()):
        return None
    if old.endswith(TEXT_SUFFIXES) or old.endswith(".toml"):
        # The snapshot folders themselves appear in `wrote PATH` lines and file names.
        la = mask(ta.decode("utf-8", "replace").replace(roots[0], "<snapshot>")).splitlines()
        lb = mask(tb.decode("utf-8", "replace").replace(roots[1], "<snapshot>")).splitlines()
        if la == lb:
            return None
        for i, (x, y) in enumerate(zip(la, lb)):
            if x != y:
                return f"line {i + 1}:\n      old: {x[:300]}\n      new: {y[:300]}"
        return f"{len(la)} vs {len(lb)} lines"
    return "bytes differ"


def files(root):
    out = set()
    for d, _, names in os.walk(root):
        for n in names:
            out.add(os.path.relpath(os.path.join(d, n), root))
    return out


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    old, new = argv[1], argv[2]
    only = argv[argv.index("--only") + 1:] if "--only" in argv else []
    fa, fb = files(old), files(new)
    names = sorted(fa | fb)
    if only:
        names = [n for n in names if any(n.startswith(p) for p in only)]
    bad = 0
    for n in names:
        if n not in fa or n not in fb:
            print(f"DIFF {n}: only in {'new' if n in fb else 'old'}")
            bad += 1
            continue
        d = compare_file(os.path.join(old, n), os.path.join(new, n), (os.path.abspath(old), os.path.abspath(new)))
        if d:
            print(f"DIFF {n}: {d}")
            bad += 1
    print(f"compared {len(names)} files: {len(names) - bad} equal, {bad} different")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
