#!/usr/bin/env python3
"""Which shared libraries programs load, by ldd. Usage:
  check_links.py --without PROGRAM... --without-geometry PROGRAM... --with PROGRAM...
Every --without program must load none of Embree, assimp, FCL, Clp or CoinUtils (the client
programs, which only talk to daemons); every --without-geometry program none of Embree, FCL, Clp
or CoinUtils (what reads scene files, with assimp, to show them); every --with program must load
Embree and assimp (what renders: the positive control that shows the check sees them). Exit 1
naming each offence."""
import re
import subprocess
import sys

PLANNING = re.compile(r"lib(embree\d*|assimp|fcl|Clp|CoinUtils)\.so")
GEOMETRY = re.compile(r"lib(embree\d*|fcl|Clp|CoinUtils)\.so")
NEEDED = ["embree", "assimp"]


def loaded(program):
    out = subprocess.run(["ldd", program], capture_output=True, text=True, check=True).stdout
    return [line.split()[0] for line in out.splitlines() if line.strip()]


def main(argv):
    mode, failures, checked = None, [], 0
    for arg in argv:
        if arg in ("--with", "--without", "--without-geometry"):
            mode = arg
            continue
        libs = loaded(arg)
        checked += 1
        if mode == "--without":
            failures += [f"{arg} loads {lib}" for lib in libs if PLANNING.search(lib)]
        elif mode == "--without-geometry":
            failures += [f"{arg} loads {lib}" for lib in libs if GEOMETRY.search(lib)]
        elif mode == "--with":
            failures += [f"{arg} does not load lib{n}" for n in NEEDED if not any(f"lib{n}" in lib for lib in libs)]
        else:
            failures.append(f"{arg}: say --with or --without first")
    for f in failures:
        print(f)
    if checked == 0:
        print("no programs given")
    return 1 if failures or checked == 0 else 0


sys.exit(main(sys.argv[1:]))
