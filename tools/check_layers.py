#!/usr/bin/env python3
"""Checks that no include runs from a lower layer of the code to a higher one.

The floors are those of docs/design.md, section 5.1 ("Layers"): the fenced block that starts with
the line "floors, lowest first". Each of its lines is a floor: a name, a colon and the folders (or
files) on it. A file may include files on its own floor and on the floors below it, never above.
Prints each violation as "FILE:LINE: <floor> includes <path> (<higher floor>)" and exits 1 if there
is any, 0 otherwise.

Usage: tools/check_layers.py [REPO_ROOT]
"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)


def read_floors():
    text = (root / "docs" / "design.md").read_text()
    block = re.search(r"```\nfloors, lowest first\n(.*?)```", text, re.S)
    if not block:
        sys.exit("check_layers: no block starting 'floors, lowest first' in docs/design.md")
    floors = []  # (name, [path prefixes])
    for line in block.group(1).splitlines():
        if not line.strip():
            continue
        name, _, places = line.partition(":")
        floors.append((name.strip(), places.split()))
    return floors


floors = read_floors()


def floor_of(rel):
    """The floor index of a path relative to the root (the longest matching prefix), or None."""
    best, best_len = None, -1
    for index, (_, places) in enumerate(floors):
        for place in places:
            if (rel == place or rel.startswith(place.rstrip("/") + "/")) and len(place) > best_len:
                best, best_len = index, len(place)
    return best


include_re = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')
violations = []
checked = 0
for path in sorted(list((root / "include").rglob("*.hpp")) + list((root / "src").rglob("*.[ch]pp"))):
    rel = path.relative_to(root).as_posix()
    here = floor_of(rel)
    if here is None:
        violations.append(f"{rel}: on no floor of docs/design.md 5.1")
        continue
    checked += 1
    for number, line in enumerate(path.read_text().splitlines(), 1):
        m = include_re.match(line)
        if not m:
            continue
        target = m.group(2)
        if target.startswith("eulervop/"):
            target_rel = "include/" + target
        elif m.group(1) == '"' and (root / "src" / target).exists():
            target_rel = "src/" + target
        else:
            continue  # a system or third-party header, or one generated at build time
        there = floor_of(target_rel)
        if there is not None and there > here:
            violations.append(f"{rel}:{number}: {floors[here][0]} includes {target} ({floors[there][0]})")

for v in violations:
    print(v)
print(f"check_layers: {checked} files, {len(violations)} violation(s)")
sys.exit(1 if violations else 0)
