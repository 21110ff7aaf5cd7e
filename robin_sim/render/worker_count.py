"""How many render processes a command may start: the one bound for episodes, replays and live.

No MuJoCo here: the command line checks the count before anything is built.
"""

from __future__ import annotations

from pil.task.param_spec import ParamSpec

# Render processes beyond this only queue for the same cores (a 640x480 frame on llvmpipe keeps
# a core busy for 30-100 ms); a cluster node with more cores runs more episodes instead.
MAX_RENDER_WORKERS = 64
RENDER_WORKERS = ParamSpec(
    "render_workers",
    "int",
    None,
    "render processes (0: in this process)",
    0,
    MAX_RENDER_WORKERS,
    optional=True,
    empty="2, or 0 on one CPU",
)
