"""Fixtures of the Python package's tests: the package from the build tree, the build's programs,
DDS test domains (locked as the C++ tests lock them), and real isparsd processes.

ctest sets ISPARS_PYTHON_PATH (build/python), ISPARS_BIN (build/bin) and ISPARS_SOURCE_DIR."""
import fcntl
import os
import pathlib
import random
import signal
import subprocess
import sys
import time

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("ISPARS_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BIN = pathlib.Path(os.environ.get("ISPARS_BIN", SOURCE_DIR / "build" / "bin"))
PACKAGE_DIR = os.environ.get("ISPARS_PYTHON_PATH", str(SOURCE_DIR / "build" / "python"))
sys.path.insert(0, PACKAGE_DIR)
SCENES = SOURCE_DIR / "deploy" / "scenes"

_held_domains = []  # open lock files: each domain stays ours until this process exits


def _take_domain():
    """A DDS domain of 1, 5, ..., 97 that no other test process holds (client/local's random_domain:
    the same lock files, the one taken longest ago first)."""
    lock_dir = pathlib.Path("/tmp/ispars-test-domains")
    lock_dir.mkdir(exist_ok=True)
    domains = [1 + 4 * i for i in range(25)]
    random.shuffle(domains)
    domains.sort(key=lambda d: (lock_dir / f"{d}.lock").stat().st_mtime if (lock_dir / f"{d}.lock").exists() else 0)
    for d in domains:
        f = open(lock_dir / f"{d}.lock", "a+")
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            f.close()
            continue
        os.utime(lock_dir / f"{d}.lock")
        _held_domains.append(f)
        return d
    raise RuntimeError("every test DDS domain (1, 5, ..., 97) is taken by a running test")


@pytest.fixture(scope="session")
def ispars():
    import ispars as module
    return module


@pytest.fixture
def domain():
    return _take_domain()


class Daemon:
    """An isparsd on `domain`, its data directory under `tmp`; stopped by SIGTERM at the end."""

    def __init__(self, domain, tmp, server_id="py", extra=()):
        self.domain = domain
        self.log_path = tmp / f"{server_id}.log"
        args = [str(BIN / "isparsd"), "--domain", str(domain), "--data-dir", str(tmp / f"data-{server_id}"),
                "--scene-dir", str(SCENES), "--server-id", server_id, "--discovery-wait-ms", "300", *extra]
        self.process = subprocess.Popen(args, stdout=open(self.log_path, "w"), stderr=subprocess.STDOUT)

    def log(self):
        return self.log_path.read_text()

    def stop(self):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        return self.process.returncode


@pytest.fixture
def daemon_factory(tmp_path):
    started = []

    def start(domain, **kw):
        d = Daemon(domain, tmp_path, **kw)
        started.append(d)
        return d

    yield start
    for d in started:
        d.stop()


def wait_for_daemon(client, server_id, seconds=30):
    """Waits until `client` lists a scene of daemon `server_id`."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        try:
            if any(e["server_id"] == server_id for e in client.scenes()):
                return
        except Exception:  # noqa: BLE001 - not seen yet
            pass
        time.sleep(0.2)
    raise AssertionError(f"daemon {server_id} not seen within {seconds} s")


def run_json(*args):
    """Runs one of the build's programs and parses the JSON object its last line prints."""
    import json
    out = subprocess.run([str(BIN / args[0]), *map(str, args[1:])], check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])
