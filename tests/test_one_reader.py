"""Every file a command reads goes through the one guarded reader (issue 39).

:mod:`pil.regular_files` opens a file only when it is a regular file (a FIFO, a device or a
folder behind a link is refused before a byte is read), reads it to a per-kind size bound and
parses it strictly. This test lists every call in ``pil/`` and ``robin_sim/`` that reads a file
(``read_text``, ``read_bytes``, ``open`` for reading, ``np.load``, ``zipfile.ZipFile``,
``yaml.load``) and holds it to :data:`ALLOWED`: the reader itself, reads of the package's own
files, and reads of a handle the guarded reader opened. Any other is a file read around the
reader, and fails here.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).parents[1]
WRITE_MODES = ("w", "a", "x", "+")

# (file, call as written) -> why it may read there
ALLOWED: dict[tuple[str, str], str] = {
    ("pil/regular_files.py", "os.fdopen"): "the reader itself",
    ("pil/task/yaml_files.py", "yaml.load"): "parses text the reader read (load_yaml_text)",
    ("robin_sim/model/pose_library.py", "read_text"): "the package's own pose library",
    ("robin_sim/vision/render_key.py", "read_bytes"): "hashes the package's own sources and models",
    ("robin_sim/live/pages.py", "read_text"): "the package's own page files",
    ("robin_sim/live/pages.py", "read_bytes"): "the package's own page files",
    ("robin_sim/replay/serve.py", "read_text"): "the package's own page files",
    ("robin_sim/lab/archive.py", "ZipFile"): "a handle open_regular opened, or the writer",
    ("robin_sim/render/state_checks.py", "ZipFile"): "a handle open_regular opened",
    ("robin_sim/render/state_checks.py", "np.load"): "a handle open_regular opened",
    ("robin_sim/vision/classifier.py", "np.load"): "a handle open_bounded opened",
    ("robin_sim/vision/dataset.py", "np.load"): "a handle open_bounded opened",
}


def _mode(node: ast.Call, position: int) -> str:
    given = node.args[position : position + 1] + [k.value for k in node.keywords if k.arg == "mode"]
    return ast.unparse(given[0]) if given else "'r'"


def _reads(node: ast.Call) -> str | None:
    """The call as this test names it when it reads a file, else None."""
    func = node.func
    if isinstance(func, ast.Name) and func.id == "open":
        mode = _mode(node, 1)
        return None if any(m in mode for m in WRITE_MODES) else f"open({mode})"
    if not isinstance(func, ast.Attribute):
        return None
    base = ast.unparse(func.value)
    if func.attr in ("read_text", "read_bytes"):
        return func.attr
    if func.attr == "fdopen" and base == "os":
        mode = _mode(node, 1)
        return None if any(m in mode for m in WRITE_MODES) else "os.fdopen"
    if func.attr == "open" and base not in ("os", "webbrowser", "av") and "hand" not in base:
        mode = _mode(node, 0)
        return None if any(m in mode for m in WRITE_MODES) else f"{base}.open({mode})"
    if func.attr == "load" and base in ("np", "numpy", "yaml", "json", "pickle"):
        return f"{base}.load"
    if func.attr == "ZipFile":
        return "ZipFile"
    return None


def file_reads() -> dict[tuple[str, str], list[int]]:
    """Every reading call in pil/ and robin_sim/: (file, call) -> its lines."""
    found: dict[tuple[str, str], list[int]] = {}
    for folder in ("pil", "robin_sim"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            where = path.relative_to(ROOT).as_posix()
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.Call) and (call := _reads(node)):
                    found.setdefault((where, call), []).append(node.lineno)
    return found


def test_every_file_read_goes_through_the_guarded_reader() -> None:
    around = {f"{f}:{lines} {call}" for (f, call), lines in file_reads().items()}
    around -= {
        f"{f}:{lines} {call}" for (f, call), lines in file_reads().items() if (f, call) in ALLOWED
    }
    assert not around, sorted(around)


def test_the_allowed_reads_are_still_there() -> None:
    """An entry of ALLOWED whose read is gone is removed, so the list stays the true one."""
    assert set(ALLOWED) <= set(file_reads()), sorted(set(ALLOWED) - set(file_reads()))


def test_the_scan_sees_a_read_around_the_reader() -> None:
    tree = ast.parse("import json\ndata = json.loads(path.read_text())\nopen(p).read()\n")
    calls = [_reads(n) for n in ast.walk(tree) if isinstance(n, ast.Call)]
    assert "read_text" in calls and "open('r')" in calls
