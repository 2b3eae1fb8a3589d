"""What the layout checks read of the CMake files: each CMakeLists.txt of ours, and the calls in
it. Imported by check_layers.py and check_namespaces.py."""
import re


def cmake_lists(root):
    """(path, text) of each CMakeLists.txt under `root`, build trees and npm packages left out."""
    for cmake in sorted(root.rglob("CMakeLists.txt")):
        rel = cmake.relative_to(root)
        if rel.parts[0].startswith("build") or "node_modules" in rel.parts:
            continue
        yield cmake, cmake.read_text()


def calls(text, command):
    """(first word, rest) of each `command(...)` call in a CMake file, comments dropped."""
    text = re.sub(r"#[^\n]*", "", text)
    for m in re.finditer(command + r"\(\s*([^\s)]+)([^)]*)\)", text):
        yield m.group(1), m.group(2).split()
