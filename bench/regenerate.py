"""Regenerate the folders of ``bench/results`` from the code, each stamped with the commit.

    python bench/regenerate.py --quick            # the learner-only folders (minutes)
    python bench/regenerate.py --full             # every folder (vision ones: hours)
    python bench/regenerate.py --only study,baselines
    python bench/regenerate.py --list             # each folder, its command and its mode

Each folder's command writes into a fresh temporary folder beside ``bench/results``; only
when it succeeds does that folder replace ``bench/results/<folder>`` (the old one is kept
until then, so a failed or interrupted run loses nothing), with ``stamp.json``: the folder,
the command, the mode, the commit (and whether the working tree had changes), the Python and
the seconds it took. ``--quick`` regenerates the folders whose command is cheap enough to run
in full; it never writes a smaller version of a folder (the docs quote the full figures), so a
folder is either regenerated as it is quoted or left as it was and listed as still due.
"""

from __future__ import annotations

import argparse
import json
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "bench" / "results"
ROBIN = [sys.executable, "-m", "robin_sim.cli.main"]
PYTHON = [sys.executable, "-m"]
SYSTEMS = "pil,proactive,c1,c2,c3,c4"
# rendered gesture data sets, kept by their render key (robin_sim.vision.render_key): a second
# run on the same body, poses and cameras reuses them; a changed one renders anew
VISION_CACHE = "out/vision_cache"  # relative to the checkout (the commands run there)


@dataclass(frozen=True)
class Recipe:
    """A results folder, the command that makes it (``--out`` is appended) and its mode."""

    folder: str
    command: tuple[str, ...]
    quick: bool  # cheap enough for --quick (learner-only, minutes at most)
    drop: tuple[str, ...] = ()  # caches the command leaves in its folder (not results)
    pages: tuple[str, ...] = ()  # files outside its folder the command writes (a docs page)

    def argv(self, out: Path) -> list[str]:
        """The command line with ``--out``."""
        if self.command[0] == "bench":  # a script of this folder
            return [
                sys.executable,
                str(ROOT / "bench" / self.command[1]),
                *self.command[2:],
                "--out",
                str(out),
            ]
        base = ROBIN if self.command[0] == "robin-pil" else PYTHON
        return [*base, *self.command[1:], "--out", str(out)]


RECIPES: tuple[Recipe, ...] = (
    Recipe(
        "study",
        ("robin-pil", "study", "--systems", SYSTEMS, "--no-progress"),
        True,
        drop=("reps.jsonl",),  # the resume journal: a cache, not a result
    ),
    Recipe("baselines", ("robin-pil", "baselines", "--no-progress"), True),
    Recipe("adapt", ("robin-pil", "adapt", "--no-progress"), True),
    Recipe("transfer", ("robin-pil", "transfer", "--no-progress"), True),
    Recipe("people", ("robin-pil", "people", "--no-progress"), True, drop=("reps.jsonl",)),
    Recipe(
        "people_40",
        ("robin-pil", "people", "--tables", "40", "--no-progress"),
        True,
        drop=("reps.jsonl",),
    ),
    Recipe("label_accuracy", ("python", "pil.experiments.label_accuracy"), True),
    Recipe("study_reading", ("python", "pil.experiments.study_reading"), False),
    Recipe("robust", ("bench", "bench_robust.py"), True),  # issue 38: the robust PIL rule
    Recipe(
        "study_seeds",
        ("robin-pil", "study", "--seeds", "10", "--systems", SYSTEMS, "--no-progress"),
        False,
    ),
    Recipe(
        "vision_conditions",
        ("robin-pil", "vision-conditions", "--no-progress"),
        False,
        drop=("chunks",),  # the rendered samples: a cache, 11 MB
    ),
    Recipe(
        "vision_dim_episodes",  # issue 38: a dim, noisy room finishes instead of an error
        (
            "robin-pil",
            "sweep",
            "--kind",
            "physical",
            "--systems",
            "pil",
            "--detector",
            "vision",
            "--param",
            "lighting=0.15",
            "--param",
            "camera_noise=40",
            "--reps",
            "10",
            "--tables",
            "1",
            "--workers",
            "2",
            "--no-progress",
        ),
        False,
    ),
    Recipe(
        "appearance",
        ("robin-pil", "people", "--appearance", "--reps", "10", "--no-progress"),
        False,
        drop=("runs",),  # each run's episode log and result: the resume journal, 8 MB
    ),
    Recipe(
        "leaderboard",  # also writes docs/leaderboard.md; refuses a tree with changes
        ("robin-pil", "bench", "--leaderboard", "--workers", "2", "--no-progress"),
        False,
        pages=("docs/leaderboard.md",),
    ),
    Recipe(
        "people_fitted",  # docs/people.md's tables then: python docs/people_tables.py
        (
            "robin-pil",
            "people",
            "--from-sessions",
            "tests/data/fitted_people/stand_ins",
            "--sessions-per-person",
            "20",
            "--workers",
            "2",
            "--no-progress",
        ),
        False,
    ),
    Recipe(
        # the capsule hand's half was measured at f581bee and the previous model's (format 2,
        # the articulated hand) at 04f787f; both are carried over
        "vision_hands",
        (
            "bench",
            "bench_vision_hands.py",
            "--hand",
            "articulated",
            "--baseline",
            str(RESULTS / "vision_hands" / "capsule.csv"),
            "--previous",
            str(RESULTS / "vision_hands" / "previous.csv"),
            "--cache",
            VISION_CACHE,
        ),
        False,
        drop=("chunks",),  # rendered samples (none with --cache: they live in VISION_CACHE)
    ),
    Recipe(
        # how much of the hand the eyes can see in vision_hands' samples, and how the shipped
        # model reads them with Robin's arm out of view (run after vision_hands: it reads that
        # recipe's articulated.csv)
        "hand_hidden",
        (
            "bench",
            "bench_hand_hidden.py",
            "--readings",
            str(RESULTS / "vision_hands" / "articulated.csv"),
            "--away",
        ),
        False,
    ),
    Recipe(
        # the model before the held-leg samples (16 128 samples, 128 units, trained on views
        # segmented without the table-top cut) is kept in the folder as other_model.npz
        "held_leg",
        (
            "bench",
            "bench_held_leg.py",
            "--other",
            str(RESULTS / "held_leg" / "other_model.npz"),
            "--other-name",
            "model before",
        ),
        False,
    ),
    Recipe(
        "vision_whole_range",
        (
            "robin-pil",
            "train-gestures",
            "--samples",
            "18144",
            "--workers",
            "2",
            "--cache",
            VISION_CACHE,
        ),
        False,
    ),
)
BY_NAME = {r.folder: r for r in RECIPES}


def commit() -> tuple[str, bool]:
    """The checked-out commit and whether the working tree has changes (bench/results aside)."""
    head = subprocess.run(
        ["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=False
    ).stdout.strip()
    status = subprocess.run(
        ["git", "status", "--porcelain", "--", ".", ":!bench/results"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    ).stdout.strip()
    return head or "unknown", bool(status)


TEXT_SUFFIXES = (".csv", ".md", ".json", ".txt")


def tidy(out: Path, written_at: str, recipe: Recipe) -> None:
    """Leave only results in ``out``: the recipe's caches removed, and the temporary path the
    command wrote into its text files (``written_at``) replaced by the folder's own."""
    for name in recipe.drop:
        shutil.rmtree(out / name, ignore_errors=True)
    final = f"bench/results/{recipe.folder}"
    for path in [*out.rglob("*"), *(ROOT / page for page in recipe.pages)]:
        if path.is_file() and path.suffix in TEXT_SUFFIXES:
            text = path.read_text()
            if written_at in text:
                path.write_text(text.replace(written_at, final))


def regenerate(recipe: Recipe, mode: str) -> float:
    """Run ``recipe`` into a temporary folder and put it in place with its stamp; seconds."""
    RESULTS.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix=f".{recipe.folder}.", dir=RESULTS))
    out = work / recipe.folder
    start = time.monotonic()
    head, dirty = commit()  # the code as it ran (the command may write docs, e.g. a page)
    try:
        done = subprocess.run(recipe.argv(out), cwd=ROOT, check=False)
        if done.returncode != 0:
            raise SystemExit(f"{recipe.folder}: the command exited {done.returncode}")
        seconds = time.monotonic() - start
        tidy(out, str(out), recipe)
        stamp = {
            "folder": recipe.folder,
            "command": " ".join(recipe.command),
            "mode": mode,
            "commit": head,
            "dirty": dirty,
            "python": platform.python_version(),
            "seconds": round(seconds, 1),
        }
        # a command that stamps its folder itself (the bench) keeps its stamp.json
        name = "regenerated.json" if (out / "stamp.json").exists() else "stamp.json"
        (out / name).write_text(json.dumps(stamp, indent=2) + "\n")
        target = RESULTS / recipe.folder
        old = work / "old"
        if target.exists():
            target.rename(old)
        out.rename(target)
        return seconds
    finally:
        shutil.rmtree(work, ignore_errors=True)


def main(argv: list[str] | None = None) -> int:
    """The command line of the module docstring."""
    parser = argparse.ArgumentParser(prog="python bench/regenerate.py")
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--quick", action="store_true", help="the cheap folders only")
    group.add_argument("--full", action="store_true", help="every folder")
    group.add_argument("--only", help="comma-separated folders")
    group.add_argument("--list", action="store_true", help="list the folders and stop")
    args = parser.parse_args(argv)
    if args.list:
        for r in RECIPES:
            print(f"{r.folder:20} {'quick' if r.quick else 'full '}  {' '.join(r.command)}")
        return 0
    if args.only:
        names = [n.strip() for n in args.only.split(",") if n.strip()]
        unknown = [n for n in names if n not in BY_NAME]
        if unknown or not names:
            print(
                f"--only: unknown folder(s) {', '.join(unknown) or '(none given)'}; "
                f"valid choices: {', '.join(BY_NAME)}",
                file=sys.stderr,
            )
            return 2
        chosen, mode = [BY_NAME[n] for n in names], "only"
    else:
        mode = "quick" if args.quick else "full"
        chosen = [r for r in RECIPES if r.quick or mode == "full"]
    for recipe in chosen:
        print(f"regenerating {recipe.folder} ...", flush=True)
        seconds = regenerate(recipe, mode)
        print(f"  {recipe.folder}: {seconds:.0f} s", flush=True)
    due = [r.folder for r in RECIPES if r not in chosen]
    if due:
        print("not regenerated (run --full or --only): " + ", ".join(due))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
