"""Dependencies by job: without an extra's package, its command names the extra in one line
(exit 2, before anything starts). The package is made unimportable in a real subprocess."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from pil.extras import EXTRAS, MissingExtraError, require_extra

ROOT = Path(__file__).resolve().parents[1]
BLOCK = "import sys; sys.modules[{module!r}] = None; from robin_sim.cli.main import main; "


def _without(module: str, argv: list[str], cwd: Path) -> subprocess.CompletedProcess:
    code = BLOCK.format(module=module) + f"sys.exit(main({argv!r}))"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, "-c", code], cwd=cwd, env=env, capture_output=True, text=True, timeout=120
    )


@pytest.mark.parametrize(
    ("extra", "argv"),
    [
        ("live", ["live", "--no-browser", "--out", "out/live"]),
        ("cluster", ["sweep", "--scheduler", "tcp://127.0.0.1:1", "--reps", "1", "--out", "out/s"]),
    ],
)
def test_a_missing_extra_is_named_in_one_line(extra: str, argv: list[str], tmp_path: Path):
    done = _without(EXTRAS[extra][0], argv, tmp_path)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and f"pip install 'robin-pil[{extra}]'" in lines[0], done.stderr
    assert not (tmp_path / "out").exists()  # nothing started, nothing written


def test_require_extra_passes_when_installed_and_names_every_extra():
    for extra in EXTRAS:
        require_extra(extra)  # the test install has them all
    with pytest.raises(KeyError):
        require_extra("gpu")
    assert issubclass(MissingExtraError, Exception)
