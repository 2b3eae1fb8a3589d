#!/usr/bin/env python3
"""docs/architecture.md against the build: it must name (in backquotes) every library and
executable that a CMakeLists.txt declares, and every target-like name it gives (ispars_*,
ispars-*, isparsd*) must be declared. Usage: check_architecture.py SOURCE_DIR. Exit 1 naming
what differs."""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
declared = {}
for cmake in root.rglob("CMakeLists.txt"):
    relative = cmake.relative_to(root)
    if relative.parts[0].startswith("build") or "node_modules" in relative.parts:
        continue
    for m in re.finditer(r"add_(library|executable)\(\s*([A-Za-z0-9_.\-]+)([^)]*)\)", cmake.read_text()):
        if "INTERFACE" in m.group(3).split() or "IMPORTED" in m.group(3).split():
            continue  # build settings or found packages, not parts of the project
        declared[m.group(2)] = str(relative)
doc = (root / "docs" / "architecture.md").read_text()
named = set(re.findall(r"`([A-Za-z0-9_.\-]+)`", doc))
missing = sorted(t for t in declared if t not in named)
unknown = sorted(n for n in named if re.fullmatch(r"(ispars[_\-]|isparsd)[A-Za-z0-9_\-]*", n) and n not in declared)
for t in missing:
    print(f"docs/architecture.md does not name {t} (declared in {declared[t]})")
for n in unknown:
    print(f"docs/architecture.md names {n}, which no CMakeLists.txt declares")
if not declared:
    print("no CMakeLists.txt targets found under", root)
sys.exit(1 if missing or unknown or not declared else 0)
