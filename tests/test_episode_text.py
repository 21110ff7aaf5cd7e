"""``robin-pil episode`` ends with a one-screen summary naming the files it wrote (``--json``:
the whole summary, as before)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from robin_sim.cli.main import main

pytestmark = pytest.mark.slow

ARGV = ["episode", "--scenario", "one_handover", "--no-video", "--no-verify", "--no-progress"]


def test_the_episode_ends_with_a_short_human_summary(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "text"
    assert main([*ARGV, "--out", str(out)]) == 0
    text = capsys.readouterr().out
    lines = text.splitlines()
    assert 6 <= len(lines) <= 20, text
    assert all(len(line) <= 100 for line in lines if not line.startswith("    /")), text
    summary = json.loads((out / "summary.json").read_text())
    assert lines[0].startswith("episode finished")
    assert f"legs delivered  {summary['legs_delivered']} of {summary['legs_total']}" in text
    assert f"robot actions   {summary['actions']} ({summary['rejected']} rejected" in text
    assert f"{summary['gestures']} instruction gestures" in text
    listed = [Path(line.split()[0]) for line in lines if line.startswith(f"    {out}")]
    assert sorted(p.name for p in listed) == ["episode.jsonl", "summary.json"]
    assert all(p.is_file() for p in listed)
    assert not text.lstrip().startswith("{")

    out = tmp_path / "json"
    assert main([*ARGV, "--json", "--out", str(out)]) == 0
    printed = json.loads(capsys.readouterr().out)
    written = json.loads((out / "summary.json").read_text())
    assert printed == written
