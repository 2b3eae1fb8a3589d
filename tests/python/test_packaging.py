"""`pip install .` as a new user runs it: a wheel from the in-tree backend, installed into fresh
venvs, imported with no PYTHONPATH, the documented example run from it; numpy missing named at
import; and the offline-only configuration (no Fast DDS) configured and its DDS-free files built.

The wheel is built from the test's build tree (-C build-dir=...), which is already built, so the
test costs seconds; docs/python.md gives the time of a clean install."""
import os
import subprocess
import sys
import zipfile

import pytest

from conftest import SOURCE_DIR

BUILD_DIR = os.environ.get("ISPARS_BUILD_DIR", str(SOURCE_DIR / "build"))
DEBIAN_PYTHON = "/usr/bin/python3"


def run(*args, env=None, cwd=None, check=True):
    clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "ISPARS_PYTHON_PATH")}
    clean.update(env or {})
    return subprocess.run([str(a) for a in args], env=clean, cwd=cwd, check=check, capture_output=True, text=True)


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    out = tmp_path_factory.mktemp("wheel")
    run(DEBIAN_PYTHON, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "-w", out,
        "--config-settings", f"build-dir={BUILD_DIR}", SOURCE_DIR, cwd=out)
    wheels = list(out.glob("ispars-*.whl"))
    assert len(wheels) == 1, wheels
    return wheels[0]


def venv(path, system_site_packages):
    run(DEBIAN_PYTHON, "-m", "venv", *(["--system-site-packages"] if system_site_packages else []), path)
    return path / "bin" / "python"


def test_the_wheel_holds_the_package_and_its_metadata(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    assert {"ispars/__init__.py", "ispars/__init__.pyi", "ispars/py.typed", "ispars/graphs.py",
            "ispars/_version.py"} <= set(names)
    assert any(n.startswith("ispars/_ispars.cpython-") and n.endswith(".so") for n in names)
    metadata = next(n for n in names if n.endswith(".dist-info/METADATA"))
    text = zipfile.ZipFile(wheel).read(metadata).decode()
    assert "Name: ispars" in text and "Requires-Dist: numpy" in text
    version = next(line.split(": ")[1] for line in text.splitlines() if line.startswith("Version: "))
    assert f"project(ispars VERSION {version}" in (SOURCE_DIR / "CMakeLists.txt").read_text()


def test_a_venv_installs_it_and_runs_the_example_offline(wheel, tmp_path):
    python = venv(tmp_path / "venv", system_site_packages=True)
    run(python, "-m", "pip", "install", "--no-index", "--no-deps", wheel)
    where = run(python, "-c", "import ispars; print(ispars.__file__, ispars.__version__, ispars.HAS_CLIENT)").stdout
    assert where.startswith(str(tmp_path / "venv")), where
    out = run(python, SOURCE_DIR / "docs" / "python_example.py", "--samples", 2000, "--budget", 0.3,
              "--out", tmp_path / "tour.png", cwd=tmp_path)
    assert "tour: cost" in out.stdout and (tmp_path / "tour.png").exists()


def test_without_numpy_the_import_names_the_fix(wheel, tmp_path):
    python = venv(tmp_path / "bare", system_site_packages=False)
    run(python, "-m", "pip", "install", "--no-index", "--no-deps", wheel)
    failed = run(python, "-c", "import ispars", check=False)
    assert failed.returncode != 0
    assert "ispars needs numpy" in failed.stderr and "--system-site-packages" in failed.stderr, failed.stderr


def test_a_bad_config_setting_is_named(tmp_path):
    failed = run(DEBIAN_PYTHON, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "-w", tmp_path,
                 "--config-settings", "client=maybe", "--config-settings", f"build-dir={tmp_path / 'b'}", SOURCE_DIR, cwd=tmp_path, check=False)
    assert failed.returncode != 0
    assert "config setting client=maybe: expected one of auto, on, off" in failed.stdout + failed.stderr


def test_the_offline_only_configuration_needs_no_dds(tmp_path):
    build = tmp_path / "offline"
    configured = run("cmake", "-S", SOURCE_DIR, "-B", build, "-G", "Ninja", "-DISPARS_DDS=OFF",
                     "-DISPARS_BUILD_TESTS=OFF", f"-DPython_EXECUTABLE={DEBIAN_PYTHON}")
    assert "Fast DDS" not in configured.stderr
    targets = run("ninja", "-C", build, "-t", "targets", "all").stdout
    assert "_ispars" in targets and "ispars-lab" in targets
    assert "isparsd" not in targets and "ispars_client" not in targets and "ispars_idl" not in targets
    links = run("ninja", "-C", build, "-t", "commands", "_ispars").stdout
    assert "fastrtps" not in links and "fastcdr" not in links
    # The module's files that differ without DDS compile (the rest are the same as in every build).
    objects = [f"client/python/CMakeFiles/_ispars.dir/src/{name}.cpp.o" for name in ("module", "errors")]
    run("ninja", "-C", build, *objects)
