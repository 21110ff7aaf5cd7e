"""The short human summary ``robin-pil episode`` prints at the end (``--json``: the full summary).

One screen: how it ended, the legs delivered, the gestures and actions it took, the times, and
the files written. The numbers come from ``summary.json`` (one source); nothing is recomputed.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pil.file_names import EPISODE_LOG_NAME, SUMMARY_NAME, VIDEO_NAME
from robin_sim.episode.config import TIME_LIMIT


def _seconds(value: float | None) -> str:
    if value is None:
        return "-"
    minutes, seconds = divmod(float(value), 60.0)
    return f"{int(minutes)} min {seconds:04.1f} s" if minutes else f"{seconds:.1f} s"


def _detection(summary: dict[str, Any]) -> str:
    """How gestures were read: the simulated detector's rate, or the eye cameras (no rate)."""
    if "vision" in summary:
        return "gestures read by Robin's eye cameras (vision)"
    return f"detection rate {summary['rate']:g}"


def summary_text(summary: dict[str, Any], out: Path) -> str:
    """The end-of-episode lines for a person reading the terminal."""
    status = summary["status"]
    ended = status if not summary.get("error") else f"{status}: {summary['error']}"
    if status == TIME_LIMIT:
        ended = f"stopped at its simulated-time limit, {_seconds(summary['sim_time_limit_s'])}"
    legs = f"{summary['legs_delivered']} of {summary['legs_total']}"
    where = f"{summary['legs_to_person']} to the person, {summary['legs_placed']} on spots"
    rate = summary.get("real_time_factor")
    lines = [
        f"episode {ended}",
        f"  run             {summary['system_name']}, scenario {summary['scenario']}",
        f"                  {_detection(summary)}, seed {summary['seed']}",
        f"  legs delivered  {legs} ({where})",
        f"  gestures        {summary['gestures']} instruction gestures, "
        f"{summary['repeats']} repeats, {summary['corrections']} corrections",
        f"  robot actions   {summary['actions']} ({summary['rejected']} rejected, "
        f"{summary['interrupted_actions']} stopped by the person, {summary['drops']} drops)",
        f"  handovers       success rate {_fraction(summary['handover_success_rate'])}, "
        f"mean {_seconds(summary['mean_handover_s'])} each",
        f"  time            {_seconds(summary['sim_time_s'])} simulated in "
        f"{_seconds(summary['wall_time_s'])} wall"
        + (f" ({rate:g}x real time)" if rate is not None else ""),
        "  files written",
    ]
    for name in (VIDEO_NAME, EPISODE_LOG_NAME, SUMMARY_NAME):
        path = out / name
        if path.exists():
            lines.append(f"    {path}  {_what(name, summary)}")
    lines.append("  (all figures: summary.json; the same as JSON: robin-pil episode --json)")
    return "\n".join(lines)


def _fraction(value: float | None) -> str:
    return "-" if value is None else f"{value:.0%}"


def _what(name: str, summary: dict[str, Any]) -> str:
    video = summary.get("video")
    if name.endswith(".mp4") and video:
        width, height = video["size"]
        return f"video, {video['frames']} frames, {width}x{height} at {video['fps']} fps"
    if name.endswith(".jsonl"):
        return f"one line per step ({summary['actions'] + summary['repeats']} steps)"
    return "every figure of the run"
