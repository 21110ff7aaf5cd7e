"""One archive per study: a ``.zip`` of the study folder with a manifest a command can check.

:func:`write_archive` puts every file of the study folder (but earlier archives and the
registry's lock) into ``archive/<study>-<UTC time>.zip`` with ``manifest.json``: the study, the
time, the robin-pil version and the source's git commit (and whether it had changes), Python's
and the main libraries' versions, the SHA-256 of the robot model files and of the protocol and
scenario files, and every archived file's SHA-256 and size, by its path relative to the study
folder. :func:`verify_archive` reads an archive back and checks every file against the
manifest: one :class:`ArchiveError` naming each file missing, changed, damaged, twice or not
listed. The manifest guards against accidents (a file changed, lost or damaged after the
export), not against someone who edits a file and its manifest entry together: for that a lab
keeps :func:`archive_digest`, the SHA-256 of the whole archive that ``study-export`` and
``study-verify`` print, somewhere else.
"""

from __future__ import annotations

import hashlib
import json
import platform
import zipfile
import zlib
from collections.abc import Iterable
from dataclasses import asdict
from datetime import UTC, datetime
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.provenance import source_commit
from pil.regular_files import LIMITS, open_regular, parse_json
from pil.task.scenario import DEFAULT_SCENARIO, find_scenario
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
    """The SHA-256 of a regular file, read in chunks (a FIFO or a device found in the study
    folder is refused, not read)."""
    digest = hashlib.sha256()
    with open_regular(path) as file:
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
    found = find_scenario(scenario) if scenario else DEFAULT_SCENARIO  # a shipped name too
    scenario_path = found if found.is_file() else None
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


def archive_digest(path: Path) -> str:
    """The SHA-256 of the whole archive file: keep it elsewhere (a lab notebook, an email) to
    tell later that the archive is the one written, manifest included."""
    digest = hashlib.sha256()
    try:
        with open_regular(path) as file:
            for chunk in iter(lambda: file.read(1 << 20), b""):
                digest.update(chunk)
    except OSError as error:
        raise ArchiveError(f"{path}: cannot read the archive: {error.strerror}") from None
    return digest.hexdigest()


def verify_archive(path: Path) -> dict[str, Any]:
    """Check every file of the archive at ``path`` against its manifest; the manifest, or an
    :class:`ArchiveError` naming each file that is missing, changed, damaged, listed twice or
    not listed.

    The archive is opened as a regular file only (a FIFO or a device is refused before a byte
    is read), the manifest is strict JSON of the expected shape, and no member is read past
    the size its manifest gives. What the check protects against: files changed, lost or
    damaged after the export (a disk, a copy, an edit by mistake). It cannot tell a manifest
    edited to match a changed file: keep :func:`archive_digest`'s digest apart from the
    archive for that.
    """
    try:
        with open_regular(path) as file, zipfile.ZipFile(file) as archive:
            names_in = archive.namelist()
            twice = sorted({name for name in names_in if names_in.count(name) > 1})
            if twice:
                raise ArchiveError(
                    f"{path}: {', '.join(twice[:5])} stands twice in the archive; an archive "
                    "written by robin-pil study-export holds each file once"
                )
            body = _read_manifest(path, archive)
            listed = _manifest_files(path, body)
            problems = [
                problem
                for name, (digest, size) in listed.items()
                if (problem := _member_problem(archive, name, digest, size, set(names_in)))
            ]
            extra = set(names_in) - set(listed) - {MANIFEST_NAME}
            problems += [f"{name}: not in the manifest" for name in sorted(extra)]
    except OSError as error:
        raise ArchiveError(
            f"{path}: cannot read the archive: {error.strerror or error}; give a "
            ".zip written by robin-pil study-export"
        ) from None
    except zipfile.BadZipFile as error:
        raise ArchiveError(
            f"{path}: not a readable study archive ({error}); give a .zip "
            "written by robin-pil study-export"
        ) from None
    if problems:
        raise ArchiveError(
            f"{path}: {len(problems)} of {len(listed)} files do not match the manifest: "
            + "; ".join(problems[:20])
        )
    return body


def _read_manifest(path: Path, archive: zipfile.ZipFile) -> dict[str, Any]:
    """The manifest of ``archive``: strict JSON, an object, read to a bounded size."""
    try:
        info = archive.getinfo(MANIFEST_NAME)
    except KeyError:
        raise ArchiveError(f"{path}: no {MANIFEST_NAME} in the archive") from None
    if info.file_size > LIMITS["settings"]:
        raise ArchiveError(f"{path}: {MANIFEST_NAME} is too large to be a manifest")
    try:
        body = parse_json(_read_member(archive, MANIFEST_NAME, info.file_size).decode("utf-8"))
    except (ValueError, UnicodeDecodeError, zipfile.BadZipFile, zlib.error) as error:
        raise ArchiveError(f"{path}: {MANIFEST_NAME} is not readable: {error}") from None
    if not isinstance(body, dict):
        raise ArchiveError(f"{path}: {MANIFEST_NAME} is not a JSON object")
    return body


def _manifest_files(path: Path, body: dict[str, Any]) -> dict[str, tuple[str, int]]:
    """The manifest's files as name -> (SHA-256, bytes); :class:`ArchiveError` naming the
    first entry that is not of that shape."""
    files = body.get("files")
    if not isinstance(files, dict):
        raise ArchiveError(
            f"{path}: {MANIFEST_NAME}: 'files' must map each file to its sha256 and bytes, "
            f"got {quote(files)}"
        )
    out = {}
    for name, entry in files.items():
        digest = entry.get("sha256") if isinstance(entry, dict) else None
        size = entry.get("bytes") if isinstance(entry, dict) else None
        if not (isinstance(digest, str) and len(digest) == 64) or type(size) is not int:
            raise ArchiveError(
                f"{path}: {MANIFEST_NAME}: the entry of {quote(name)} must be "
                '{"sha256": 64 hex digits, "bytes": a whole number}'
            )
        out[name] = (digest, size)
    return out


def _read_member(archive: zipfile.ZipFile, name: str, size: int) -> bytes:
    """Member ``name``'s bytes, never more than ``size`` + 1 of them."""
    with archive.open(name) as member:
        return member.read(size + 1)


def _member_problem(
    archive: zipfile.ZipFile, name: str, digest: str, size: int, names_in: set[str]
) -> str:
    """What is wrong with member ``name`` against its manifest entry ("" when nothing)."""
    if name not in names_in:
        return f"{name}: missing"
    try:
        data = _read_member(archive, name, max(size, 0))
    except (zipfile.BadZipFile, zlib.error, EOFError) as error:
        return f"{name}: its stored data is damaged ({error})"
    if len(data) != size or sha256(data) != digest:
        return f"{name}: changed (its checksum differs from the manifest's)"
    return ""
