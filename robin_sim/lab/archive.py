"""One archive per study: a ``.zip`` of the study folder with a manifest a command can check.

:func:`write_archive` puts every file of the study folder (but earlier archives and the
registry's lock) into ``archive/<study>-<UTC time>.zip`` with ``manifest.json``: the study, the
time, the robin-pil version and the source's git commit (and whether it had changes), Python's
and the main libraries' versions, the SHA-256 of the robot model files and of the protocol and
scenario files, and every archived file's SHA-256 and size, by its path relative to the study
folder. :func:`verify_archive` reads an archive back and checks every file against the
manifest: one :class:`ArchiveError` naming each file missing, changed or not listed.
"""

from __future__ import annotations

import hashlib
import json
import platform
import zipfile
from collections.abc import Iterable
from dataclasses import asdict
from datetime import UTC, datetime
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.provenance import source_commit
from robin_sim.lab.registry import LOCK_NAME
from robin_sim.lab.study_file import Study
from robin_sim.model import names

ARCHIVE_DIR = "archive"
MANIFEST_NAME = "manifest.json"
ARCHIVE_FORMAT = 1
LIBRARIES = ("mujoco", "numpy", "scipy", "statsmodels", "pandas", "aiohttp")
MODEL_FILES = {"scene": names.SCENE_XML, "robot": names.ROBOT_XML}


class ArchiveError(RobinPilError):
    """An archive that cannot be read or does not match its manifest."""


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def file_hash(path: Path) -> str:
    digest = hashlib.sha256()
    with Path(path).open("rb") as file:
        for chunk in iter(lambda: file.read(1 << 20), b""):
            digest.update(chunk)
    return digest.hexdigest()


def study_files(study: Study) -> list[Path]:
    """The study folder's files that an archive holds, sorted (relative paths)."""
    root = study.folder
    skipped = (root / ARCHIVE_DIR,)
    found = []
    for path in sorted(root.rglob("*")):
        if not path.is_file() or path.is_symlink() or path.name == LOCK_NAME:
            continue
        if any(path.is_relative_to(s) for s in skipped):
            continue
        found.append(path.relative_to(root))
    return found


def manifest(study: Study, files: Iterable[Path], robin_pil_version: str) -> dict[str, Any]:
    """The manifest of an archive of ``files`` (relative to the study folder)."""
    libraries: dict[str, str | None] = {}
    for name in LIBRARIES:
        try:
            libraries[name] = version(name)
        except PackageNotFoundError:
            libraries[name] = None
    protocol = Path(study.protocol.source)
    scenario = study.protocol.scenario
    scenario_path = Path(scenario) if scenario and Path(scenario).is_file() else None
    return {
        "format": ARCHIVE_FORMAT,
        "study": study.name,
        "design": study.design,
        "created_utc": datetime.now(UTC).isoformat(timespec="seconds"),
        "robin_pil": {"version": robin_pil_version, "commit": asdict(source_commit())},
        "python": platform.python_version(),
        "libraries": libraries,
        "models": {name: file_hash(path) for name, path in MODEL_FILES.items()},
        "protocol": {"name": study.protocol_ref, "sha256": file_hash(protocol)},
        "scenario": {
            "name": scenario or "default",
            "sha256": None if scenario_path is None else file_hash(scenario_path),
        },
        "files": {
            p.as_posix(): {
                "sha256": file_hash(study.folder / p),
                "bytes": (study.folder / p).stat().st_size,
            }
            for p in files
        },
    }


def write_archive(study: Study, robin_pil_version: str) -> Path:
    """Write the study's archive (see the module doc); its path."""
    files = study_files(study)
    body = manifest(study, files, robin_pil_version)
    stamp = datetime.now(UTC).strftime("%Y%m%d-%H%M%S")
    folder = study.folder / ARCHIVE_DIR
    folder.mkdir(exist_ok=True)
    path, n = folder / f"{study.name}-{stamp}.zip", 1
    while path.exists():
        n += 1
        path = folder / f"{study.name}-{stamp}-{n}.zip"
    temp = path.with_suffix(".part")
    try:
        with zipfile.ZipFile(temp, "w", zipfile.ZIP_DEFLATED) as archive:
            archive.writestr(MANIFEST_NAME, json.dumps(body, indent=2) + "\n")
            for relative in files:
                archive.write(study.folder / relative, relative.as_posix())
        temp.replace(path)
    finally:
        temp.unlink(missing_ok=True)
    return path


def verify_archive(path: Path) -> dict[str, Any]:
    """Check every file of the archive at ``path`` against its manifest; the manifest, or an
    :class:`ArchiveError` naming each file that is missing, changed or not listed."""
    try:
        with zipfile.ZipFile(path) as archive:
            body = json.loads(archive.read(MANIFEST_NAME))
            listed = body["files"]
            problems = []
            names_in = set(archive.namelist()) - {MANIFEST_NAME}
            for name, expected in listed.items():
                if name not in names_in:
                    problems.append(f"{name}: missing")
                    continue
                data = archive.read(name)
                if sha256(data) != expected["sha256"] or len(data) != expected["bytes"]:
                    problems.append(f"{name}: changed (its checksum differs from the manifest's)")
            problems += [f"{name}: not in the manifest" for name in sorted(names_in - set(listed))]
    except (OSError, zipfile.BadZipFile, KeyError, ValueError, TypeError) as error:
        raise ArchiveError(
            f"{quote(str(path))}: not a readable study archive ({error}); give a .zip "
            "written by robin-pil study-export"
        ) from None
    if problems:
        raise ArchiveError(
            f"{path}: {len(problems)} of {len(listed)} files do not match the manifest: "
            + "; ".join(problems[:20])
        )
    return body
