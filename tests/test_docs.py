"""The docs tell the truth about the CLI: every command line in README.md, docs/ and bench/README.md
parses with the real parser, every option they name exists, every relative link resolves, the
README stays a front door (at most 200 lines) and its Python example runs."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from robin_sim.cli.main import COMMANDS, build_parser

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")), ROOT / "bench" / "README.md"]
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def _blocks(page: Path, language: str) -> list[str]:
    return [m.group(2) for m in FENCE.finditer(page.read_text()) if m.group(1) == language]


def _command_lines() -> list[tuple[str, list[str]]]:
    """(where, argv) for each `robin-pil ...` segment of a shell line in a bash block."""
    found = []
    for page in PAGES:
        for block in _blocks(page, "bash"):
            for line in block.replace("\\\n", " ").splitlines():
                code = line.split(" #", 1)[0].strip()
                for segment in re.split(r"&&|\|\||;|\|", code):
                    segment = segment.strip()
                    if not segment.startswith("robin-pil") or "$(" in segment:
                        continue
                    where = f"{page.relative_to(ROOT)}: {line.strip()}"
                    found.append((where, shlex.split(segment)[1:]))
    return found


COMMAND_LINES = _command_lines()


def test_the_docs_have_command_lines_to_check():
    assert len(COMMAND_LINES) >= 20
    assert {argv[0] for _, argv in COMMAND_LINES if argv} >= {"episode", "study", "sweep", "live"}


@pytest.mark.parametrize(("where", "argv"), COMMAND_LINES, ids=[w for w, _ in COMMAND_LINES])
def test_every_documented_command_line_parses(where: str, argv: list[str], capsys):
    if not argv or argv[0].startswith("-"):
        with pytest.raises(SystemExit) as stop:
            build_parser().parse_args(argv)
        assert stop.value.code == 0, f"{where}: refused by the parser"
        return
    assert argv[0] in COMMANDS, f"{where}: no command {argv[0]!r}"
    try:
        build_parser(argv[0]).parse_args(argv)
    except SystemExit as stop:
        assert stop.value.code == 0, f"{where}: {capsys.readouterr().err.strip()}"


# The documented command lines fast enough to run in the tests (seconds, learner only), by
# page; each page's run in its order in a fresh folder (a report reads the study before it).
RUN_IN_TESTS: dict[str, tuple[str, ...]] = {
    "docs/commands.md": (
        "robin-pil model-path",
        "robin-pil study --reps 2 --tables 1 --rates 1.0 --systems pil,c1 --out out/first",
        "robin-pil report out/first/runs.csv --out out/first/report",
    ),
    "docs/architecture.md": (
        "robin-pil sweep --systems pil,c1 --rates 1.0 --reps 1 --tables 1 --workers 1 "
        "--no-report --out out/spine",
    ),
    "docs/model-and-control.md": ("robin-pil model-path",),
}


@pytest.mark.slow
@pytest.mark.parametrize("page", sorted(RUN_IN_TESTS))
def test_the_fast_documented_command_lines_run(
    page: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Each line of :data:`RUN_IN_TESTS` is on its page and runs there (exit 0), in order."""
    from robin_sim.cli.main import main

    documented = [
        shlex.split(line.split(" #", 1)[0])
        for block in _blocks(ROOT / page, "bash")
        for line in block.replace("\\\n", " ").splitlines()
    ]
    monkeypatch.chdir(tmp_path)
    for line in RUN_IN_TESTS[page]:
        argv = shlex.split(line)
        assert argv in documented, f"{page} no longer documents: {line}"
        assert main(argv[1:] + (["--no-progress"] if argv[1] in PROGRESS else [])) == 0, (
            f"{page}: {line}: {capsys.readouterr().err}"
        )
        if "--out" in argv:  # what the line says it writes is there
            written = tmp_path / argv[argv.index("--out") + 1]
            assert written.is_dir() and any(written.iterdir()), line
        else:  # model-path prints the model's file
            assert Path(capsys.readouterr().out.strip()).is_file(), line


PROGRESS = {"study", "sweep"}  # their bar is switched off in the tests (not in the docs)


def test_the_model_and_control_model_example_runs() -> None:
    """docs/model-and-control.md's first example: a scene of a layout, a hand sensor."""
    example = _blocks(ROOT / "docs" / "model-and-control.md", "python")[0]
    names: dict[str, object] = {}
    exec(compile(example, "model-and-control.md", "exec"), names)
    model = names["model"]
    assert getattr(model, "nbody", 0) > 0 and names["sensor"] is not None


def _options(command: str) -> set[str]:
    parser = build_parser(command)
    sub = next(a for a in parser._actions if a.dest == "command").choices[command]
    return {s for action in sub._actions for s in action.option_strings}


def test_every_option_named_in_the_docs_exists():
    """Inline code like `robin-pil study [--rates ...]` names only options the command has."""
    options = {name: _options(name) for name in COMMANDS}
    bad = []
    for page in PAGES:
        text = FENCE.sub("", page.read_text())
        for span in re.findall(r"`(robin-pil [^`]+)`", text):
            words = span.split()
            if len(words) < 2 or words[1] not in COMMANDS:
                if len(words) > 1 and not words[1].startswith(("-", "[", "...")):
                    bad.append(f"{page.name}: unknown command in `{span}`")
                continue
            for flag in re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", span):
                if flag not in options[words[1]]:
                    bad.append(f"{page.name}: `{span}` names {flag}, not an option of {words[1]}")
    assert not bad, "\n".join(bad)


def test_relative_links_resolve():
    bad = []
    for page in PAGES:
        for target in LINK.findall(FENCE.sub("", page.read_text())):
            if re.match(r"[a-z]+:", target) or target.startswith("#"):
                continue
            path = target.split("#", 1)[0]
            if not (page.parent / path).exists():
                bad.append(f"{page.relative_to(ROOT)}: {target}")
    assert not bad, "\n".join(bad)


def test_readme_is_a_front_door():
    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) <= 200
    first = _blocks(ROOT / "README.md", "bash")[0]
    commands = [line for line in first.splitlines() if line and not line.startswith("#")]
    assert commands == [
        "python3 -m venv .venv && . .venv/bin/activate && pip install -e . && robin-pil episode",
        'python3 -m venv .venv && . .venv/bin/activate && pip install -e ".[test]" && pytest -n 2',
    ]
    for page in PAGES[1:]:
        assert page.relative_to(ROOT).as_posix() in readme, f"README does not link {page.name}"


@pytest.mark.slow
def test_the_readme_python_example_runs(tmp_path: Path):
    (example,) = _blocks(ROOT / "README.md", "python")
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MUJOCO_GL": "egl"}
    done = subprocess.run(
        [sys.executable, "-c", example],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["finished", "1", "of", "1"]
    assert (tmp_path / "out" / "api" / "summary.json").is_file()


@pytest.mark.slow
def test_the_architecture_python_example_runs(tmp_path: Path):
    """docs/architecture.md's example: a RunSpec parsed once and assembled, learner-only and
    physical, and an episode through the public API (``from robin_sim import ...``)."""
    (example,) = _blocks(ROOT / "docs" / "architecture.md", "python")
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MUJOCO_GL": "egl"}
    done = subprocess.run(
        [sys.executable, "-c", example],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[:3] == ["c1 40 legs", "True True", "finished 1 of 1"]
    assert (tmp_path / "out" / "api" / "summary.json").is_file()


def test_the_study_walkthrough_runs(tmp_path: Path, monkeypatch, capsys) -> None:
    """docs/live.md's walk-through of a study, on a fresh folder: every command runs but
    ``live`` and ``replay``, which are parsed; each ``live`` line registers its participant
    as the command does before it serves (the page itself: tests/browser/test_browser_study.py)."""
    import glob

    from robin_sim.cli.main import main
    from robin_sim.lab.run import prepare
    from robin_sim.live.config import LiveConfig

    section = (ROOT / "docs" / "live.md").read_text().split("### From the study file to the report")
    block = FENCE.search(section[1])
    assert block is not None and block.group(1) == "bash"
    monkeypatch.chdir(tmp_path)
    ran = []
    for line in block.group(2).splitlines():
        argv = shlex.split(line.split(" #", 1)[0])[1:]
        if argv[0] in ("live", "replay"):
            args = build_parser(argv[0]).parse_args(argv)
            if argv[0] == "live":
                for _ in range(1 if args.participant else 3):
                    prepare(args.study, args.participant, LiveConfig(video=False))
            continue
        expanded = [m for a in argv for m in (sorted(glob.glob(a)) or [a])]
        assert main(expanded) == 0, f"{line}: {capsys.readouterr().err}"
        ran.append(argv[0])
    assert ran == [
        "study-init",
        "study-status",
        "study-status",
        "study-withdraw",
        "report",
        "study-export",
        "study-verify",
    ]
    out = capsys.readouterr().out
    assert "| P03 | g1" not in out  # within: group all
    registry = (tmp_path / "pilot" / "registry.json").read_text()
    assert '"P07"' in registry and '"withdrawn"' in registry
    assert "files match the manifest" in out
