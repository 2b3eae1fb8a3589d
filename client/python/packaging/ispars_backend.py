"""The build backend (PEP 517) of `pip install .`: the project's CMake builds the module.

It needs nothing but the standard library, CMake and the project's Debian packages, so it works
offline and without build isolation. The wheel holds build/.../python/ispars/ as the CMake build
lays it out (the same files `PYTHONPATH=build/python` imports). Config settings (--config-settings KEY=VALUE):

- client: auto (default; the DDS client when Fast DDS is found), on (fail without it) or off;
- build-dir: CMake's build directory, default build/pip-<tag> in the source tree (kept, so a
  second install compiles only what changed); an existing configured build is reused as it is;
- jobs: parallel compile jobs (default: the machine's cores).
"""

import io
import os
import re
import shutil
import subprocess
import sys
import tarfile
from pathlib import Path

import wheel_file

_SOURCE = Path(__file__).resolve().parents[3]
_CLIENT_CHOICES = {"auto": "AUTO", "on": "ON", "off": "OFF"}


class BackendError(RuntimeError):
    """A build that cannot go on, with what to do about it."""


def _project():
    try:
        import tomllib  # Python 3.11
    except ImportError:  # earlier Pythons: the tomli package, when installed
        try:
            import tomli as tomllib
        except ImportError as e:
            raise BackendError("reading pyproject.toml needs Python 3.11 or the tomli package") from e
    with open(_SOURCE / "pyproject.toml", "rb") as f:
        return tomllib.load(f)["project"]


def _version():
    """CMakeLists.txt's project(ispars VERSION x.y.z): the one place the version is written."""
    text = (_SOURCE / "CMakeLists.txt").read_text(encoding="utf-8")
    match = re.search(r"project\(ispars\s+VERSION\s+([0-9][0-9.]*)", text)
    if not match:
        raise BackendError("CMakeLists.txt has no project(ispars VERSION x.y.z)")
    return match.group(1)


def _setting(config_settings, key, default):
    value = (config_settings or {}).get(key, default)
    if isinstance(value, list):  # pip passes a repeated KEY as a list
        value = value[-1]
    return str(value)


def _build_dir(config_settings):
    given = _setting(config_settings, "build-dir", "")
    if given:
        return Path(given).expanduser().resolve()
    return _SOURCE / "build" / f"pip-{wheel_file.platform_tag()}"


def _run(command, what):
    print("ispars_backend:", " ".join(str(c) for c in command), flush=True)
    try:
        subprocess.run([str(c) for c in command], check=True, cwd=_SOURCE)
    except FileNotFoundError as e:
        raise BackendError(f"{what}: {command[0]} is not installed (deploy/install-deps.sh installs it)") from e
    except subprocess.CalledProcessError as e:
        raise BackendError(f"{what} failed (exit {e.returncode}); its output is above") from e


def _configure(build_dir, config_settings):
    client = _setting(config_settings, "client", "auto").lower()
    if client not in _CLIENT_CHOICES:
        raise BackendError(f"config setting client={client}: expected one of {', '.join(_CLIENT_CHOICES)}")
    if (build_dir / "CMakeCache.txt").exists() and _setting(config_settings, "build-dir", ""):
        return  # a build the user made: reused as configured
    command = ["cmake", "-S", _SOURCE, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DISPARS_BUILD_TESTS=OFF",
               "-DISPARS_PYTHON=ON", f"-DISPARS_DDS={_CLIENT_CHOICES[client]}", f"-DPython_EXECUTABLE={sys.executable}"]
    if shutil.which("ninja") and not (build_dir / "CMakeCache.txt").exists():
        command += ["-G", "Ninja"]
    _run(command, "configuring with CMake")


def _package_files(build_dir):
    """The files of build_dir/python/ispars/ as {archive name: bytes}."""
    package = build_dir / "python" / "ispars"
    files = {}
    for path in sorted(package.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            files[path.relative_to(package.parent).as_posix()] = path.read_bytes()
    if not any(name.startswith("ispars/_ispars") for name in files):
        raise BackendError(f"the build made no extension module in {package}")
    return files


# PEP 517 hooks.

def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    return wheel_file.write_dist_info(metadata_directory, _project(), _version())


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    build_dir = _build_dir(config_settings)
    _configure(build_dir, config_settings)
    jobs = _setting(config_settings, "jobs", str(os.cpu_count() or 1))
    if not jobs.isdigit() or int(jobs) < 1:
        raise BackendError(f"config setting jobs={jobs}: expected a whole number of jobs, 1 or more")
    _run(["cmake", "--build", build_dir, "--target", "_ispars", "--parallel", jobs], "building the module")
    return wheel_file.write_wheel(wheel_directory, _project(), _version(), _package_files(build_dir))


def _source_files():
    """The tracked files (git ls-files), or every file outside build output when there is no git."""
    try:
        listed = subprocess.run(["git", "ls-files", "-z"], cwd=_SOURCE, check=True, capture_output=True).stdout
        return sorted(name for name in listed.decode().split("\0") if name)
    except (OSError, subprocess.CalledProcessError):
        skip = {"build", ".git", "node_modules", "__pycache__"}
        return sorted(p.relative_to(_SOURCE).as_posix() for p in _SOURCE.rglob("*")
                      if p.is_file() and not skip.intersection(p.relative_to(_SOURCE).parts))


def build_sdist(sdist_directory, config_settings=None):
    project, version = _project(), _version()
    top = f"{project['name']}-{version}"
    path = Path(sdist_directory) / f"{top}.tar.gz"
    pkg_info = wheel_file.metadata_text(project, version).encode()
    with tarfile.open(path, "w:gz", format=tarfile.PAX_FORMAT) as archive:
        for name in _source_files():
            source = _SOURCE / name
            if source.is_file():
                archive.add(source, arcname=f"{top}/{name}", recursive=False)
        info = tarfile.TarInfo(f"{top}/PKG-INFO")
        info.size = len(pkg_info)
        archive.addfile(info, io.BytesIO(pkg_info))
    return path.name
