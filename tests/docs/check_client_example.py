#!/usr/bin/env python3
"""docs/service.md's C++ client example must be, line for line, the body of docs_service_example()
in tests/client/client_headers_check.cpp, which the build compiles against the public headers.
Usage: check_client_example.py SOURCE_DIR. Exit 1 naming the first line that differs."""
import pathlib
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
doc = (root / "docs" / "service.md").read_text()
check = (root / "tests" / "client" / "client_headers_check.cpp").read_text()
try:
    example = doc.split("## The C++ client library", 1)[1].split("```cpp", 1)[1].split("```", 1)[0]
    body = check.split("void docs_service_example() {", 1)[1].split("\n}\n", 1)[0]
except IndexError:
    sys.exit("docs/service.md has no C++ client example, or the check has no docs_service_example()")
wanted = [l.strip() for l in example.splitlines() if l.strip() and not l.startswith("#include")]
compiled = [l.strip() for l in body.splitlines() if l.strip()]
for i, (a, b) in enumerate(zip(wanted, compiled)):
    if a != b:
        sys.exit(f"line {i + 1} of the example differs:\n  docs:  {a}\n  check: {b}")
if len(wanted) != len(compiled):
    sys.exit(f"the example has {len(wanted)} lines, the compiled copy {len(compiled)}")
