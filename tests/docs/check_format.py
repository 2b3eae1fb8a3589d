#!/usr/bin/env python3
"""Every C++ file of ours is as clang-format leaves it (.clang-format at the top). Usage:
check_format.py SOURCE_DIR [CLANG_FORMAT]. Exit 1 naming each file that is not, with the command
that fixes it; exit 2 when clang-format is missing (deploy/install-deps.sh installs it)."""
import pathlib
import shutil
import subprocess
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
tool = sys.argv[2] if len(sys.argv) > 2 else shutil.which("clang-format")
if not tool:
    print("clang-format not found: deploy/install-deps.sh installs it (Debian's clang-format)")
    sys.exit(2)

def ours(path):
    parts = path.relative_to(root).parts
    return not parts[0].startswith("build") and not {".git", "node_modules"} & set(parts[:-1])


files = sorted(p for ext in ("*.cpp", "*.hpp") for p in root.rglob(ext) if ours(p))
bad = []
for i in range(0, len(files), 100):
    run = subprocess.run([tool, "--dry-run", "--Werror", *map(str, files[i:i + 100])],
                         capture_output=True, text=True)
    bad += sorted({line.split(":")[0] for line in run.stderr.splitlines() if ": error:" in line})
for f in bad:
    print(f"{pathlib.Path(f).relative_to(root.resolve()) if pathlib.Path(f).is_absolute() else f}: not formatted "
          f"(clang-format -i {f})")
print(f"{len(files)} files, {len(bad)} not formatted")
sys.exit(1 if bad else 0)
