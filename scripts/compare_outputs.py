#!/usr/bin/env python3
"""Compare two output snapshots (scripts/snapshot_outputs.sh) file by file.

Usage: scripts/compare_outputs.py OLD_DIR NEW_DIR [--only PREFIX ...]

Equal means bit for bit, outside what measures the machine rather than the result:
- JSON: the keys `timing`, `provenance`, `wall_s`, `elapsed_s`, `search_s`, `seconds` and keys ending
  in `_wall_s` are dropped at any depth; every other value (floats included) must be equal.
- Text (standard output and error, HTML, Markdown, TOML comments): wall times (`12.34 s`, `(5.1 s wall)`,
  `in 0.123 s`, `µs per filter step`) and the tool version line are masked before comparing.
- Everything else (CSV, SVG, XML, TOML): byte for byte.
A file present on one side only is a difference. Exit code 0 when all equal, 1 otherwise.
"""

import json
import os
import re
import sys

DROP_KEYS = {"timing", "provenance", "wall_s", "elapsed_s", "search_s", "seconds", "generated_by"}
TIME_PATTERNS = [
    (re.compile(r"\d+(\.\d+)?(e-?\d+)? ?(µs|us|ms|s)\b( wall| in all| per \w+)?"), "<time>"),
    (re.compile(r"\d+(\.\d+)?x faster"), "<speed-up>"),
    (re.compile(r"(entrynav|version) \d+\.\d+\.\d+[^\s\"<]*"), "<version>"),
]
TEXT_SUFFIXES = (".stdout", ".stderr", ".html", ".md", ".txt")


def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if k not in DROP_KEYS and not k.endswith("_wall_s")}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v


def mask(text):
    for pat, rep in TIME_PATTERNS:
        text = pat.sub(rep, text)
    return text


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


def compare_file(old, new):
    if old.endswith(".json"):
        try:
            a, b = json.load(open(old)), json.load(open(new))
        except ValueError:
            pass
        else:
            return first_difference(strip(a), strip(b))
    ta, tb = open(old, "rb").read(), open(new, "rb").read()
    if ta == tb:
        return None
    if old.endswith(TEXT_SUFFIXES) or old.endswith(".toml"):
        la = mask(ta.decode("utf-8", "replace")).splitlines()
        lb = mask(tb.decode("utf-8", "replace")).splitlines()
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
        d = compare_file(os.path.join(old, n), os.path.join(new, n))
        if d:
            print(f"DIFF {n}: {d}")
            bad += 1
    print(f"compared {len(names)} files: {len(names) - bad} equal, {bad} different")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
