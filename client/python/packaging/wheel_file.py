"""A wheel (PEP 427) written from a directory of files: the archive, its dist-info and RECORD.

Only what `pip install` reads: METADATA (core metadata 2.1), WHEEL with one tag, RECORD with
each file's sha256 and size. The package's files go under the wheel's root (platlib).
"""

import base64
import hashlib
import sysconfig
import sys
import zipfile
from pathlib import Path

# Entries get a fixed time so that the same files give the same wheel, byte for byte.
_EPOCH = (1980, 1, 1, 0, 0, 0)


def platform_tag():
    """This interpreter's tag, as pip matches it: e.g. cp311-cp311-linux_x86_64."""
    impl = f"cp{sys.version_info.major}{sys.version_info.minor}"
    plat = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{impl}-{impl}-{plat}"


def metadata_text(project, version):
    """Core metadata (METADATA) from pyproject.toml's [project] table and the version."""
    lines = [
        "Metadata-Version: 2.1",
        f"Name: {project['name']}",
        f"Version: {version}",
        f"Summary: {project.get('description', '')}",
        f"Requires-Python: {project.get('requires-python', '>=3')}",
    ]
    lines += [f"Requires-Dist: {d}" for d in project.get("dependencies", [])]
    for extra, deps in sorted(project.get("optional-dependencies", {}).items()):
        lines.append(f"Provides-Extra: {extra}")
        lines += [f"Requires-Dist: {d}; extra == \"{extra}\"" for d in deps]
    return "\n".join(lines) + "\n"


def dist_info_name(project, version):
    return f"{project['name']}-{version}.dist-info"


def write_dist_info(directory, project, version):
    """Writes NAME-VERSION.dist-info/METADATA into `directory`; returns the folder's name."""
    name = dist_info_name(project, version)
    folder = Path(directory) / name
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "METADATA").write_text(metadata_text(project, version), encoding="utf-8")
    return name


def _record_line(arcname, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{arcname},sha256={digest},{len(data)}"


def write_wheel(wheel_directory, project, version, files):
    """Writes the wheel holding `files` ({archive name: bytes}); returns the wheel's file name."""
    tag = platform_tag()
    dist_info = dist_info_name(project, version)
    entries = dict(sorted(files.items()))
    entries[f"{dist_info}/METADATA"] = metadata_text(project, version).encode()
    entries[f"{dist_info}/WHEEL"] = (
        f"Wheel-Version: 1.0\nGenerator: ispars_backend\nRoot-Is-Purelib: false\nTag: {tag}\n").encode()
    record = [_record_line(name, data) for name, data in entries.items()]
    record.append(f"{dist_info}/RECORD,,")
    entries[f"{dist_info}/RECORD"] = ("\n".join(record) + "\n").encode()
    wheel_name = f"{project['name']}-{version}-{tag}.whl"
    path = Path(wheel_directory) / wheel_name
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, data in entries.items():
            info = zipfile.ZipInfo(name, date_time=_EPOCH)
            info.external_attr = 0o644 << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            archive.writestr(info, data)
    return wheel_name
