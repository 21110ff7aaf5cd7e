"""Write docs/people.md's tables from the results of ``robin-pil people --from-sessions``.

    python docs/people_tables.py [RESULTS]   # default: bench/results/people_fitted

Each table sits between ``<!-- NAME -->`` and ``<!-- /NAME -->`` in docs/people.md and is
made here from the results files only (``people/*.json``, ``comparison.csv``);
``tests/test_people_fit.py`` checks that the page holds what this script writes.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from pil.experiments.people_compare import read_comparison, summary_table  # noqa: E402

PAGE = ROOT / "docs" / "people.md"
RESULTS = ROOT / "bench" / "results" / "people_fitted"


def _latency(value: dict | None) -> str:
    if value is None:
        return "–"
    return (
        f"{value['median']:.2f} s [{value['median_low']:.2f}, {value['median_high']:.2f}], "
        f"σ {value['sigma']:.2f}, n {value['n']}"
    )


def _rate(value: dict) -> str:
    if value["p"] is None:
        return "–"
    return f"{value['p']:.2f} [{value['low']:.2f}, {value['high']:.2f}] ({value['k']}/{value['n']})"


def fitted_table(results: Path) -> str:
    """The fitted people's parameters, one column per person."""
    people = [json.loads(p.read_text()) for p in sorted((results / "people").glob("*.json"))]
    rows = [
        ("recorded sessions", lambda p: str(len(p["sources"]))),
        ("gesture latency (median [95 % CI])", lambda p: _latency(p["gesture_latency"])),
        ("thumb-down latency from the action's start", lambda p: _latency(p["down_latency"])),
        ("thumb-up latency from the action's start", lambda p: _latency(p["up_latency"])),
        ("thumb down on a wrong arm move", lambda p: _rate(p["down_on_wrong_move"])),
        ("thumb down on a wrong close / open", lambda p: _rate(p["down_on_wrong_fingers"])),
        ("thumb down on a right action (a slip)", lambda p: _rate(p["down_on_right"])),
        ("thumb up on a right action (else silence)", lambda p: _rate(p["up_on_right"])),
        ("thumbs after the window (late)", lambda p: str(p["late_thumbs"])),
    ]
    lines = [
        "| fitted | " + " | ".join(p["participant"] for p in people) + " |",
        "|---|" + "---|" * len(people),
    ]
    lines += [f"| {name} | " + " | ".join(cell(p) for p in people) + " |" for name, cell in rows]
    return "\n".join(lines)


def tables(results: Path) -> dict[str, str]:
    """Every table of the page by its marker's name."""
    return {
        "fitted-people": fitted_table(results),
        "comparison": summary_table(read_comparison(results / "comparison.csv")),
    }


def section(text: str, name: str) -> str:
    """What the page holds between ``name``'s markers."""
    found = re.search(rf"<!-- {name} -->\n(.*?)\n<!-- /{name} -->", text, re.S)
    if found is None:
        raise SystemExit(f"{PAGE}: no <!-- {name} --> section")
    return found.group(1)


def main() -> None:
    results = Path(sys.argv[1]) if len(sys.argv) > 1 else RESULTS
    text = PAGE.read_text(encoding="utf-8")
    for name, table in tables(results).items():
        old = section(text, name)
        text = text.replace(f"<!-- {name} -->\n{old}\n", f"<!-- {name} -->\n{table}\n", 1)
    PAGE.write_text(text, encoding="utf-8")
    print("wrote", PAGE)


if __name__ == "__main__":
    main()
