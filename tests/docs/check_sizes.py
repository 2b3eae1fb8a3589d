#!/usr/bin/env python3
"""No function of ours is over 80 lines, and no class has its member functions defined in more
than 3 files (docs/architecture.md, "Sizes"). Usage: check_sizes.py SOURCE_DIR. The lab's
experiments (common/lab/experiment_*.cpp) and the tests are exempt.

A function is a brace block opened right after a closing parenthesis (with const, noexcept,
override or a trailing return type between), not after if, for, while, switch or catch: lambdas
count. Its length is from the line of its opening brace to the line of its closing one. Comments,
strings and raw strings are blanked first. A class's member functions are the definitions
`Name::member(` that start a line. Exit 1 naming each one over."""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
MAX_LINES = 80
MAX_FILES = 3


def ours(path):
    rel = path.relative_to(root)
    parts = rel.parts
    if parts[0].startswith("build") or parts[0] in ("tests", ".git") or "node_modules" in parts:
        return False
    return not (parts[:2] == ("common", "lab") and re.match(r"experiment_", parts[-1]))


def blank(src):
    """The source with comments, strings and character literals replaced by spaces (lines kept)."""
    out, i, n = [], 0, len(src)
    while i < n:
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
        elif src.startswith("/*", i):
            j = src.find("*/", i) + 2
        elif src.startswith('R"', i):
            delim = src[i + 2:src.find("(", i)]
            j = src.find(")" + delim + '"', i) + len(delim) + 2
        elif src[i] in "\"'" and not (src[i] == "'" and i > 0 and src[i - 1].isalnum()):
            j = i + 1
            while j < n and src[j] != src[i]:
                j += 2 if src[j] == "\\" else 1
            j += 1
        else:
            out.append(src[i])
            i += 1
            continue
        out.append(re.sub(r"[^\n]", " ", src[i:j]))
        i = j
    return "".join(out)


SIGNATURE_END = re.compile(r"\)\s*(?:const|noexcept|override|final|mutable|\s)*(?:->\s*[\w:<>,\s*&]+)?$")
CONTROL = re.compile(r"\b(if|for|while|switch|catch)\s*$")


def long_functions(path, text):
    found, stack = [], []
    for m in re.finditer(r"[{}]", text):
        at = m.start()
        if text[at] == "{":
            before = text[max(0, at - 400):at].rstrip()
            is_function = False
            sig = SIGNATURE_END.search(before)
            if sig:
                k, depth = sig.start(), 0
                while k >= 0:  # the '(' that opens the parameter list
                    depth += {")": 1, "(": -1}.get(before[k], 0)
                    if before[k] == "(" and depth == 0:
                        break
                    k -= 1
                is_function = k > 0 and not CONTROL.search(before[:k])
            stack.append((at, is_function))
        elif stack:
            start, is_function = stack.pop()
            lines = text.count("\n", start, at) + 1
            if is_function and lines > MAX_LINES:
                found.append(f"{path}:{text.count(chr(10), 0, start) + 1}: a function of {lines} lines "
                             f"(at most {MAX_LINES})")
    return found


DEFINITION = re.compile(r"^(?![ \t])(?:[\w:<>,*&]+[ \t]+)*(?:\w+::)*(\w+)::~?\w+\s*\(", re.M)

files = sorted(p for ext in ("*.cpp", "*.hpp") for p in root.rglob(ext) if ours(p))
problems, defined_in, namespaces = [], {}, set()
for f in files:
    text = blank(f.read_text(errors="replace"))
    rel = f.relative_to(root)
    problems += long_functions(rel, text)
    namespaces |= set(re.findall(r"\bnamespace\s+(?:\w+::)*(\w+)", text))
    if f.suffix == ".cpp":
        for name in DEFINITION.findall(text):
            defined_in.setdefault(name, set()).add(str(rel))
for name, where in sorted(defined_in.items()):
    if name not in namespaces and len(where) > MAX_FILES:
        problems.append(f"{name}: member functions in {len(where)} files (at most {MAX_FILES}): "
                        + ", ".join(sorted(where)))
for p in problems:
    print(p)
print(f"{len(files)} files, {len(problems)} over")
sys.exit(1 if problems else 0)
