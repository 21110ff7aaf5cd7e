"""matplotlib for every figure of the reports: pyplot on the Agg backend, and writing a figure.

:func:`pyplot` imports pyplot late (it is slow to import) with the Agg backend, so figures are
drawn without a display; :func:`finish_figure` titles, lays out and writes a figure, leaving no
half file behind when the disk fills up.
"""

from __future__ import annotations

from pathlib import Path
from types import ModuleType
from typing import Any


def pyplot() -> ModuleType:
    """matplotlib's pyplot on the Agg backend."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def finish_figure(plt: ModuleType, fig: Any, title: str | None, path: str | Path) -> Path:
    """Title (if given), lay out and write ``fig`` to ``path``, then free it."""
    if title is not None:
        fig.suptitle(title)
    fig.tight_layout()
    try:
        return save_figure(fig, path)
    finally:
        plt.close(fig)


def save_figure(fig: Any, path: str | Path) -> Path:
    """Write ``fig`` to ``path`` (PNG, via a temporary file so no half file is left)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.name + ".partial")
    try:
        fig.savefig(partial, dpi=120, format=path.suffix.lstrip(".") or "png")
        partial.replace(path)
    except BaseException:  # a full disk: no half figure left beside the finished files
        partial.unlink(missing_ok=True)
        raise
    return path
