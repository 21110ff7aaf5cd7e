"""The wheel carries everything an episode needs: the MJCF models and the scenarios.

``.ci/run`` installs this wheel into a fresh virtual environment and runs an episode from an
empty folder; this test checks the wheel's contents against the source tree.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# source folder -> where its files sit inside the wheel (package data)
SHIPPED = {
    "models": "robin_sim/model/mjcf",
    "scenarios": "pil/task/scenarios",
    "robin_sim/live/static/vendor": "robin_sim/live/static/vendor",  # the --webcam tracker
}


# what a clone does not have: a source copy without these builds like a fresh clone (setuptools
# would otherwise pack stale modules left in build/lib)
NOT_IN_A_CLONE = (".venv", "build", "dist", "out", "*.egg-info", "__pycache__", ".*_cache", ".git")


@pytest.mark.slow
def test_wheel_contains_the_models_and_scenarios(tmp_path: Path) -> None:
    source = tmp_path / "source"
    shutil.copytree(ROOT, source, symlinks=True, ignore=shutil.ignore_patterns(*NOT_IN_A_CLONE))
    build = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "--quiet",
            str(source),
            "-w",
            str(tmp_path / "dist"),
        ],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert build.returncode == 0, build.stderr[-2000:]
    (wheel,) = (tmp_path / "dist").glob("robin_pil-*.whl")
    with zipfile.ZipFile(wheel) as archive:
        contents = {name: archive.read(name) for name in archive.namelist()}
    for source, packaged in SHIPPED.items():
        files = sorted(p for p in (ROOT / source).rglob("*") if p.is_file())
        assert files, f"nothing under {source}/"
        for path in files:
            inside = f"{packaged}/{path.relative_to(ROOT / source).as_posix()}"
            assert inside in contents, f"{inside} is missing from {wheel.name}"
            assert contents[inside] == path.read_bytes(), f"{inside} differs from {path}"
    entry_points = next(v for k, v in contents.items() if k.endswith(".dist-info/entry_points.txt"))
    assert b"robin-pil = robin_sim.cli.main:main" in entry_points
    tops = {name.split("/")[0] for name in contents}
    packages = {top for top in tops if not top.endswith(".dist-info")}
    assert {"pil", "robin_sim"} <= packages and not packages & {"tests", "bench", "models"}
    modules = {name for name in contents if name.endswith(".py")}
    sources = {
        p.relative_to(ROOT).as_posix() for pkg in packages for p in (ROOT / pkg).rglob("*.py")
    }
    assert modules == sources  # every module, and nothing stale
