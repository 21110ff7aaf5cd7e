"""Every bench script still runs: each one with ``--smoke`` (tiny sizes, real code paths).

The benches measure; these runs only show that they work (a bench that crashes cannot
re-measure the README's figures). A new ``bench/bench_*.py`` is picked up here by its name.
Marked ``bench_smoke``: the suite's addopts leave them out; ``pytest -n 2 -m bench_smoke`` runs
them (``.ci/run`` does, after the README's test command).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = [pytest.mark.slow, pytest.mark.bench_smoke]  # run by: pytest -n 2 -m bench_smoke

BENCH = Path(__file__).resolve().parents[1] / "bench"
SCRIPTS = sorted(BENCH.glob("bench_*.py"))


def test_every_bench_is_found() -> None:
    assert len(SCRIPTS) >= 13 and (BENCH / "bench_physics.py") in SCRIPTS


@pytest.mark.parametrize("script", SCRIPTS, ids=[s.stem for s in SCRIPTS])
def test_the_bench_runs_in_smoke_mode(script: Path, tmp_path: Path) -> None:
    root = BENCH.parent
    path = os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")])
    env = {**os.environ, "PYTHONPATH": path}
    done = subprocess.run(
        [sys.executable, str(script), "--smoke"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "Traceback" not in done.stderr
    assert done.stdout.strip(), "a bench prints its figures"
