#!/usr/bin/env python3
"""The layers of docs/architecture.md against the code: each library in its table may include
headers only of the libraries above it. A library's headers are those under the include roots
its CMakeLists.txt gives it (target_include_directories); its code is the sources it declares
(add_library) and the headers beside them. Usage: check_layers.py SOURCE_DIR [--print]. Exit 1
naming each include that reaches down or sideways; --print also prints the graph."""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
doc = (root / "docs" / "architecture.md").read_text()
layers = re.findall(r"^\| `([A-Za-z0-9_]+)` \|", doc, re.M)  # the table's rows, top to bottom

include_roots, sources = {}, {}
for cmake in root.rglob("CMakeLists.txt"):
    rel = cmake.relative_to(root)
    if rel.parts[0].startswith("build") or "node_modules" in rel.parts:
        continue
    text = cmake.read_text()
    for m in re.finditer(r"target_include_directories\(\s*(\S+)\s+(?:SYSTEM\s+)?PUBLIC\s+([^)]*)\)", text):
        for d in m.group(2).split():
            path = d.replace("${CMAKE_CURRENT_SOURCE_DIR}", str(cmake.parent))
            include_roots.setdefault(m.group(1), []).append(pathlib.Path(path))
    for m in re.finditer(r"add_library\(\s*(\S+)\s+STATIC\s+([^)]*)\)", text):
        sources[m.group(1)] = [cmake.parent / s for s in m.group(2).split() if s.endswith(".cpp")]

owner = {}  # header path as included -> library
for lib, dirs in include_roots.items():
    for d in dirs:
        for h in d.rglob("*.hpp"):
            owner.setdefault(str(h.relative_to(d)), lib)

problems, graph = [], {}
for lib in layers:
    files = set(sources.get(lib, []))
    for src in list(files):
        files.update(src.parent.glob("*.hpp"))
    for d in include_roots.get(lib, []):
        files.update(d.rglob("*.hpp"))
    if not files:
        problems.append(f"{lib}: no sources found for a library the table names")
    used = set()
    for f in sorted(files):
        for m in re.finditer(r'#include "([^"]+)"', f.read_text()):
            other = owner.get(m.group(1))
            if other is None or other == lib:
                continue
            used.add(other)
            if other not in layers or layers.index(other) > layers.index(lib):
                problems.append(f"{f.relative_to(root)} ({lib}) includes {m.group(1)} of {other}, "
                                "which is not above it in docs/architecture.md")
    graph[lib] = sorted(used, key=lambda x: layers.index(x) if x in layers else 99)
if "--print" in sys.argv:
    for lib in layers:
        print(f"{lib:18} includes {', '.join(graph.get(lib, [])) or 'nothing of the others'}")
for p in problems:
    print(p)
if len(layers) < 2:
    print("no library table found in docs/architecture.md")
sys.exit(1 if problems or len(layers) < 2 else 0)
