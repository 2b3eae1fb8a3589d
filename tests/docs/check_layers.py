#!/usr/bin/env python3
"""The layers of the code, read from the CMake files: every library and program of ours may include
only the headers of the libraries it links (target_link_libraries, any visibility) and of those
they link PUBLIC, in turn; nothing it reaches only through a PRIVATE link of another. A target's
headers are those under its include roots (target_include_directories); its code is the sources
it declares (add_library, add_executable) and the headers beside them. An include root a target
names by hand (a header check) counts as linked. Beside that, each link
between the libraries of docs/architecture.md's table goes up the table (no cycle, no link down).
Usage: check_layers.py SOURCE_DIR [--print]. Exit 1 naming each include or link that breaks a
rule; --print also prints what each target includes of the others."""
import pathlib
import re
import sys

from cmake_calls import calls, cmake_lists

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
doc = (root / "docs" / "architecture.md").read_text()
layers = re.findall(r"^\| `([A-Za-z0-9_]+)` \|", doc, re.M)  # the table's rows, top to bottom


include_roots, named_dirs, sources, links = {}, {}, {}, {}
for cmake, text in cmake_lists(root):
    here = cmake.parent
    for name, words in calls(text, "target_include_directories"):
        visibility = None
        for w in words:
            if w in ("PUBLIC", "PRIVATE", "INTERFACE", "SYSTEM"):
                visibility = w if w != "SYSTEM" else visibility
            elif visibility in ("PUBLIC", "INTERFACE") and "CMAKE_CURRENT_SOURCE_DIR" in w:
                include_roots.setdefault(name, []).append(pathlib.Path(w.replace("${CMAKE_CURRENT_SOURCE_DIR}", str(here))))
            elif "PROJECT_SOURCE_DIR" in w:  # another library's include root, named by hand
                named_dirs.setdefault(name, []).append(pathlib.Path(w.replace("${PROJECT_SOURCE_DIR}", str(root))))
    for command in ("add_library", "add_executable"):
        for name, words in calls(text, command):
            files = [here / w for w in words if w.endswith(".cpp")]
            if files:
                sources.setdefault(name, []).extend(files)
    for name, words in calls(text, "target_link_libraries"):
        visibility = "PUBLIC"  # a plain signature's links are PUBLIC
        for w in words:
            if w in ("PUBLIC", "PRIVATE", "INTERFACE"):
                visibility = w
            else:
                links.setdefault(name, []).append((w, visibility))

owner = {}  # a header path as included -> the library whose include root holds it
for lib, dirs in include_roots.items():
    for d in dirs:
        for h in d.rglob("*.hpp"):
            owner.setdefault(str(h.relative_to(d)), lib)


def public_closure(target, seen=None):
    """`target` and what it links PUBLIC (or INTERFACE), in turn."""
    seen = set() if seen is None else seen
    if target in seen:
        return seen
    seen.add(target)
    for other, visibility in links.get(target, []):
        if visibility in ("PUBLIC", "INTERFACE"):
            public_closure(other, seen)
    return seen


problems, graph = [], {}
ours = sorted(set(sources) & (set(links) | set(include_roots)))
for target in ours:
    allowed = {target}
    for other, _ in links.get(target, []):
        allowed |= public_closure(other)
    for d in named_dirs.get(target, []):  # a header check compiled against an include root by hand
        allowed |= {lib for lib, dirs in include_roots.items() if d.resolve() in [x.resolve() for x in dirs]}
    files = set(sources.get(target, []))
    for src in list(files):
        files.update(src.parent.glob("*.hpp"))
    for d in include_roots.get(target, []):
        files.update(d.rglob("*.hpp"))
    used = set()
    for f in sorted(files):
        if not f.exists():
            continue
        for m in re.finditer(r'#include "([^"]+)"', f.read_text()):
            other = owner.get(m.group(1))
            if other is None or other == target:
                continue
            used.add(other)
            if other not in allowed:
                problems.append(f"{f.relative_to(root)} ({target}) includes {m.group(1)} of {other}, "
                                "which it does not link (directly, or through a PUBLIC link)")
    graph[target] = sorted(used)

for lib in layers:
    if lib not in sources:
        problems.append(f"{lib}: no sources found for a library the table names")
    for other, _ in links.get(lib, []):
        if other in layers and layers.index(other) >= layers.index(lib):
            problems.append(f"{lib} links {other}, which is not above it in docs/architecture.md")

if "--print" in sys.argv:
    for target in ours:
        print(f"{target:26} includes {', '.join(graph[target]) or 'nothing of the others'}")
for p in problems:
    print(p)
if len(layers) < 2:
    print("no library table found in docs/architecture.md")
sys.exit(1 if problems or len(layers) < 2 else 0)
