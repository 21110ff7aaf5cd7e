"""Optional dependencies by job: the core install runs episodes and studies; a command that
needs an extra says which one to install, in one line, before it starts."""

from __future__ import annotations

import importlib

from pil.errors import RobinPilError

#: extra -> (the module it brings, what it is for)
EXTRAS: dict[str, tuple[str, str]] = {
    "cluster": ("distributed", "a sweep on a Dask cluster (--scheduler)"),
    "live": ("aiohttp", "the live page's web server (robin-pil live)"),
}


class MissingExtraError(RobinPilError):
    """A command needs an optional dependency that is not installed."""


def require_extra(extra: str) -> None:
    """Raise :class:`MissingExtraError` unless ``extra``'s module imports."""
    module, purpose = EXTRAS[extra]
    try:
        importlib.import_module(module)
    except ImportError:
        raise MissingExtraError(
            f"{purpose} needs the {extra!r} extra ({module} is not installed): "
            f"pip install 'robin-pil[{extra}]'"
        ) from None
