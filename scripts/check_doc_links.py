#!/usr/bin/env python3
"""Every relative Markdown link in README.md, ARCHITECTURE.md and docs/*.md resolves: the file
exists and, for a link into a Markdown file with #anchor, the file has a heading with that
GitHub-style anchor. Links in fenced code blocks and absolute URLs are not checked.
Usage: python3 scripts/check_doc_links.py   (from anywhere; exit 1 listing each broken link)"""
import glob
import os
import re
import sys

os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
LINK = re.compile(r"\]\(([^)\s]+)\)")


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def lines_outside_fences(path):
    fence = False
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            if line.startswith("```"):
                fence = not fence
            elif not fence:
                yield n, line


def anchors(path):
    found, seen = set(), {}
    for _, line in lines_outside_fences(path):
        if re.match(r"#{1,6} ", line):
            s = slug(line.lstrip("#"))
            k = seen.get(s, 0)
            seen[s] = k + 1
            found.add(s if k == 0 else f"{s}-{k}")
    return found


broken = []
files = ["README.md", "ARCHITECTURE.md", *sorted(glob.glob("docs/*.md"))]
for doc in files:
    for n, line in lines_outside_fences(doc):
        for m in LINK.finditer(line):
            target = m.group(1)
            if re.match(r"[a-zA-Z][a-zA-Z0-9+.-]*:", target):
                continue
            path, _, anchor = target.partition("#")
            resolved = os.path.normpath(os.path.join(os.path.dirname(doc), path)) if path else doc
            if not os.path.exists(resolved):
                broken.append(f"{doc}:{n}: {target}: no such file")
            elif anchor and resolved.endswith(".md") and anchor not in anchors(resolved):
                broken.append(f"{doc}:{n}: {target}: no heading with that anchor in {resolved}")
for b in broken:
    print(b, file=sys.stderr)
if broken:
    sys.exit(1)
print(f"doc links: every relative link in {len(files)} files resolves")
