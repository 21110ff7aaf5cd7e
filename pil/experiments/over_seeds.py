"""Claims over seeds: one whole study per master seed, and each headline as a mean with its
95 % interval over the seeds (independent studies, so the seeds are the sample).

:func:`run_seeds` runs (or, for a seed whose folder already holds a finished run with the
same settings, reads back) each seed's study into ``OUT/seed_<n>/``, where every seed keeps
its own rows, ``tests.csv`` and summary; :func:`tests_over_seeds` turns the seeds' paired tests
into one row per comparison: the mean difference over seeds with its interval and how many
seeds found it significant (Holm-adjusted p < 0.05) in either direction.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.errors import RobinPilError
from pil.experiments.report import Row, group_rows, load_rows, markdown_table, number_or_nan
from pil.experiments.stats import PAIRED_T, WELCH, mean_ci
from pil.regular_files import UnreadableFileError, read_kind_text

SETTINGS_FILE = "settings.json"  # written last: a seed folder with it holds a finished run
MAX_SEEDS = 1000
OVER_SEEDS_COLUMNS: tuple[str, ...] = (
    "test",
    "seeds",
    "mean_diff",
    "ci_low",
    "ci_high",
    "seeds_a_more",
    "seeds_a_less",
    "seeds_untestable",
)


def check_seed_count(count: Any, option: str = "--seeds") -> int:
    """``count`` as a whole number of seeds from 1 to :data:`MAX_SEEDS`."""
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= MAX_SEEDS:
        raise RobinPilError(f"{option} must be a whole number from 1 to {MAX_SEEDS}, got {count!r}")
    return count


def seed_folder(out: Path, seed: int) -> Path:
    """Where seed ``seed``'s study lives under ``out``."""
    return out / f"seed_{seed}"


def _settings_text(settings: Mapping[str, Any], seed: int) -> str:
    return json.dumps({**settings, "seed": seed}, indent=1, sort_keys=True, default=str) + "\n"


def _read_settings(path: Path) -> str:
    try:
        return read_kind_text(path, "settings", "the study's settings")
    except UnreadableFileError as error:
        raise RobinPilError(f"{error}; use another --out") from None


def check_seed_folders(out: Path, seeds: Sequence[int], settings: Mapping[str, Any]) -> None:
    """Refuse, before anything runs, a seed folder that holds a study with other settings."""
    for seed in seeds:
        path = seed_folder(out, seed) / SETTINGS_FILE
        if os.path.lexists(path) and _read_settings(path) != _settings_text(settings, seed):
            raise RobinPilError(
                f"{path.parent} holds a study with other settings (see {path}); use another "
                "--out, or the same settings to resume"
            )


def run_seeds(
    out: Path,
    seeds: Sequence[int],
    settings: Mapping[str, Any],
    rows_file: str,
    run_one: Callable[[int], list[dict[str, Any]]],
    write_one: Callable[[int, list[dict[str, Any]], Path], object],
    skipped: Callable[[int], None] | None = None,
) -> dict[int, Sequence[Row]]:
    """Each seed's rows: read back from ``seed_<n>/<rows_file>`` where that folder holds a
    finished run with ``settings`` (``skipped(seed)`` is told), else run (``run_one(seed)``)
    and written there (``write_one(seed, rows, folder)``, then the settings file)."""
    check_seed_folders(out, seeds, settings)
    found: dict[int, Sequence[Row]] = {}
    for seed in seeds:
        folder = seed_folder(out, seed)
        if (folder / SETTINGS_FILE).is_file() and (folder / rows_file).is_file():
            found[seed] = load_rows(folder / rows_file)
            if skipped is not None:
                skipped(seed)
            continue
        rows = run_one(seed)
        write_one(seed, rows, folder)
        write_text_atomic(folder / SETTINGS_FILE, _settings_text(settings, seed))
        found[seed] = rows
    return found


def tests_over_seeds(
    tests_by_seed: Mapping[int, Sequence[Row]], within: Sequence[str] = ("rate",)
) -> list[dict[str, Any]]:
    """One row per comparison (measure, reading, ``within``, system_a, system_b) of the
    seeds' paired t-tests (Welch where unpaired): the mean difference a - b over seeds with
    its 95 % interval, the seeds where a needs significantly more / less, and those where
    the test had no spread to work on (``seeds_untestable``)."""
    rows = [
        dict(t) for tests in tests_by_seed.values() for t in tests if t["test"] in (PAIRED_T, WELCH)
    ]
    if not rows:
        return []
    keys = ["measure", "reading", *within, "system_a", "system_b"]
    out = []
    for key, members in group_rows(rows, keys).items():
        diffs = [number_or_nan(m["mean_diff"], "mean_diff") for m in members]
        mean, low, high = mean_ci([d for d in diffs if not math.isnan(d)])

        def significant(sign: int, members: list[Row] = members) -> int:
            return sum(
                1
                for m in members
                if not math.isnan(number_or_nan(m["p_holm"], "p_holm"))
                and number_or_nan(m["p_holm"], "p_holm") < 0.05
                and sign * number_or_nan(m["mean_diff"], "mean_diff") > 0
            )

        out.append(
            {
                **dict(zip(keys, key, strict=True)),
                "test": "/".join(sorted({str(m["test"]) for m in members})),
                "seeds": len(members),
                "mean_diff": mean,
                "ci_low": low,
                "ci_high": high,
                "seeds_a_more": significant(1),
                "seeds_a_less": significant(-1),
                "seeds_untestable": sum(
                    1 for m in members if math.isnan(number_or_nan(m["p_holm"], "p_holm"))
                ),
            }
        )
    return out


def over_seeds_columns(within: Sequence[str] = ("rate",)) -> list[str]:
    """The columns of ``seeds_tests.csv``."""
    return ["measure", "reading", *within, "system_a", "system_b", *OVER_SEEDS_COLUMNS]


def interval(mean: float, low: float, high: float, spec: str = ".1f") -> str:
    """``mean [low, high]`` (``n/a`` bounds where there is no interval)."""
    if math.isnan(low):
        return f"{mean:{spec}}"
    return f"{mean:{spec}} [{low:{spec}}, {high:{spec}}]"


def over_seeds_markdown(
    rows: Sequence[Mapping[str, Any]], within: Sequence[str] = ("rate",)
) -> str:
    """A table of :func:`tests_over_seeds` rows."""
    header = [
        "measure",
        "reading",
        *within,
        "a",
        "b",
        "test",
        "seeds",
        "a − b over seeds [95 % CI]",
        "seeds a more (Holm p < 0.05)",
        "seeds a less",
        "seeds untestable",
    ]
    body = [
        [
            r["measure"],
            r["reading"] or "-",
            *(r[c] for c in within),
            r["system_a"],
            r["system_b"],
            r["test"],
            r["seeds"],
            interval(r["mean_diff"], r["ci_low"], r["ci_high"]),
            r["seeds_a_more"],
            r["seeds_a_less"],
            r["seeds_untestable"],
        ]
        for r in rows
    ]
    return markdown_table(header, body)


def write_tests_over_seeds(
    out: Path, seeds: Sequence[int], within: Sequence[str], title: str
) -> list[Path]:
    """``seeds_tests.csv`` and ``seeds.md`` under ``out`` from each seed folder's
    ``tests.csv`` (a small study's headline over seeds); their paths."""
    from pil.experiments.study import csv_text

    tests_by_seed = {s: load_rows(seed_folder(out, s) / "tests.csv") for s in seeds}
    over = tests_over_seeds(tests_by_seed, within)
    text = "\n".join(
        [
            f"# {title} over {len(seeds)} seeds",
            "",
            f"Master seeds {seeds[0]}-{seeds[-1]}, each the whole study in `seed_<n>/` (its own "
            "CSV, summary and tests.csv). Per comparison: the seeds' paired-t mean differences "
            "a - b, their mean with a 95 % t-interval over seeds (the seeds are independent "
            "studies), and the seeds where a is significantly above / below b (Holm-adjusted "
            "p < 0.05 within the seed).",
            "",
            over_seeds_markdown(over, within),
            "",
        ]
    )
    return [
        write_text_atomic(out / "seeds_tests.csv", csv_text(over, over_seeds_columns(within))),
        write_text_atomic(out / "seeds.md", text),
    ]
