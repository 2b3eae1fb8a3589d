#!/usr/bin/env python3
"""Each library's own namespace and include path, read from the CMake files: every library of ours
(add_library with sources) keeps its public headers under one folder `ispars/<name>/` of its include
roots, and its code (its sources, the headers beside them and under its include roots) opens one
namespace of ours, `ispars::<name>` (nested ones below it allowed), which no other library opens.
The roadmap library, the vocabulary every other one speaks (Vec3, Roadmap, PoiId), owns `ispars`
itself, as drake/common owns `drake` (docs/architecture.md, "Namespaces"). Programs and tests may
open any namespace. Usage: check_namespaces.py SOURCE_DIR. Exit 1 naming each file that breaks a
rule."""
import pathlib
import re
import sys

from cmake_calls import calls, cmake_lists

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
ROOT_OWNER = "ispars_roadmap"
GENERATED = {"ispars_idl"}
FORWARD = re.compile(r"^namespace [\w:]+ \{\n(?:(?:class|struct) \w+;[^\n]*\n)+\}[^\n]*$", re.M)  # fastddsgen's code, in the IDL's module namespace


sources, include_roots = {}, {}
for cmake, text in cmake_lists(root):
    if "vendor" in cmake.relative_to(root).parts:
        continue
    here = cmake.parent
    for name, words in calls(text, "add_library"):
        files = [here / w for w in words if w.endswith(".cpp")]
        if files and name not in GENERATED and "OBJECT" not in words:
            sources.setdefault(name, []).extend(files)
    for name, words in calls(text, "target_include_directories"):
        public = False
        for w in words:
            if w in ("PUBLIC", "INTERFACE", "PRIVATE"):
                public = w != "PRIVATE"
            elif public and "CMAKE_CURRENT_SOURCE_DIR" in w:
                include_roots.setdefault(name, []).append(pathlib.Path(w.replace("${CMAKE_CURRENT_SOURCE_DIR}", str(here))))
            elif public and not w.startswith("$") and w != "SYSTEM":
                include_roots.setdefault(name, []).append(here / w)

problems = []
owners = {}  # namespace -> library
for lib in sorted(sources):
    files = set(sources[lib])
    for f in sources[lib]:
        files |= set(f.parent.glob("*.hpp"))
    folders = set()
    for d in include_roots.get(lib, []):
        for h in d.rglob("*.hpp"):
            files.add(h)
            parts = h.relative_to(d).parts
            if len(parts) < 3 or parts[0] != "ispars":
                problems.append(f"{h.relative_to(root)}: a public header of {lib} outside ispars/<library>/")
            else:
                folders.add(parts[1])
    if len(folders) > 1:
        problems.append(f"{lib}'s public headers lie in {len(folders)} folders: ispars/{', ispars/'.join(sorted(folders))}")
    opened = {}
    for f in sorted(files):
        text = FORWARD.sub("", f.read_text())  # a block of forward declarations names another's types
        for m in re.finditer(r"^namespace (ispars(?:::\w+)?)(?:::\w+)* \{", text, re.M):
            opened.setdefault(m.group(1), f)
    want = "ispars" if lib == ROOT_OWNER else ("ispars::" + next(iter(folders)) if len(folders) == 1 else None)
    for ns, f in sorted(opened.items()):
        if want is not None and ns != want:
            problems.append(f"{f.relative_to(root)}: {lib} opens namespace {ns}, not its own ({want})")
        elif ns in owners and owners[ns] != lib:
            problems.append(f"{f.relative_to(root)}: {lib} opens namespace {ns}, which {owners[ns]} opens too")
        owners.setdefault(ns, lib)
if not sources:
    problems.append(f"no libraries found under {root}")
for p in problems:
    print(p)
sys.exit(1 if problems else 0)
