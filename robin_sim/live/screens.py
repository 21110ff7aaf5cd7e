"""The screens around a study's blocks: consent first, demographics, and the debrief last.

A study file (:mod:`robin_sim.lab.study_file`) defines them::

    consent:
      title: Taking part in this study
      text: |
        You will teach a simulated robot ... You may stop at any time.
      agree: I agree to take part
      decline: I do not agree
    demographics:            # a form: choice, number and text items (robin_sim.live.questionnaires)
      items:
        - {id: age, text: Your age in years, kind: number, min: 18, max: 99}
    debrief:
      text: Thank you! The study compared two ways of learning ...

The page shows consent and the debrief as one screen each (phases ``consent`` and
``debrief``) and the demographics as a form (phase ``questionnaire``). It sends
``{"type": "consent", "value": "agree" | "decline"}`` and, on the debrief, ``{"type":
"finish"}`` (:mod:`robin_sim.live.inputs`). Pure Python.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass
from typing import Any

from pil.errors import RobinPilError, quote
from robin_sim.live.items import Questionnaire
from robin_sim.live.questionnaires import load_form

CONSENT_KEYS = ("title", "text", "agree", "decline")
DEBRIEF_KEYS = ("title", "text", "button")
MAX_SCREEN_TEXT = 8000  # characters of a consent or debrief text
MAX_LABEL = 80


class ScreenError(RobinPilError):
    """A consent, demographics or debrief screen that is malformed."""


@dataclass(frozen=True)
class Consent:
    """The consent screen: its text and the two answers' buttons."""

    text: str
    title: str = "Taking part in this study"
    agree: str = "I agree to take part"
    decline: str = "I do not agree"

    def as_dict(self) -> dict[str, Any]:
        return {
            "title": self.title,
            "text": self.text,
            "agree": self.agree,
            "decline": self.decline,
        }


@dataclass(frozen=True)
class Debrief:
    """The last screen: what the study was about, and a button that ends the run."""

    text: str
    title: str = "Thank you"
    button: str = "Finish"

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class Screens:
    """A study's screens around its blocks (each optional)."""

    consent: Consent | None = None
    demographics: Questionnaire | None = None
    debrief: Debrief | None = None


def load_screens(raw: Mapping[str, Any], where: str) -> Screens:
    """The ``consent``, ``demographics`` and ``debrief`` entries of a study file, checked."""
    consent = raw.get("consent")
    demographics = raw.get("demographics")
    debrief = raw.get("debrief")
    return Screens(
        None if consent is None else Consent(**_fields(consent, CONSENT_KEYS, f"{where}: consent")),
        None
        if demographics is None
        else load_form(demographics, f"{where}: demographics", "demographics"),
        None if debrief is None else Debrief(**_fields(debrief, DEBRIEF_KEYS, f"{where}: debrief")),
    )


def _fields(raw: Any, keys: tuple[str, ...], where: str) -> dict[str, str]:
    if isinstance(raw, str):
        raw = {"text": raw}
    if not isinstance(raw, Mapping) or "text" not in raw:
        raise ScreenError(
            f"{where}: expected a text, or a mapping with 'text' (keys: {', '.join(keys)})"
        )
    unknown = [str(k) for k in raw if k not in keys]
    if unknown:
        raise ScreenError(
            f"{where}: unknown key {quote(unknown[0])}; valid keys: " + ", ".join(keys)
        )
    fields = {}
    for key, value in raw.items():
        longest = MAX_SCREEN_TEXT if key == "text" else MAX_LABEL
        if not isinstance(value, str) or not value.strip() or len(value) > longest:
            raise ScreenError(
                f"{where}.{key}: expected a text of 1 to {longest} characters, got {quote(value)}"
            )
        fields[key] = value.strip()
    return fields


PHASE_MESSAGES = {  # what the page says on each screen between sessions
    "waiting": "waiting for the participant's tab",
    "consent": "please read the information and answer",
    "instructions": "read the instructions, then press Start",
    "starting": "starting the session...",
    "questionnaire": "please answer the questionnaire",
    "debrief": "please read, then press Finish",
}
SHOWN_AS = {"done": "done", "consent": "consent", "debrief": "debrief"}  # else instructions


def between_status(
    phase: str,
    config: Any,
    outcome: str | None,
    extra: dict[str, Any],
    last: dict[str, Any],
    screens: Screens,
    asking: dict[str, Any] | None,
) -> dict[str, Any]:
    """The page's status between sessions: ``config`` is the block the screen belongs to,
    ``extra`` the run's fields, ``last`` the last ended session's status, ``asking`` the
    questionnaire shown (:meth:`Questioning.status`)."""
    base = {**_screen_status(config, phase, outcome), **extra}
    if phase == "questionnaire" and asking is not None:
        return {**base, **last, **extra, **asking}
    if phase == "consent" and screens.consent is not None:
        return {**base, "consent": screens.consent.as_dict()}
    if phase == "debrief" and screens.debrief is not None:
        shown = {"phase": "debrief", "status": "running", "debrief": screens.debrief.as_dict()}
        return {**base, **last, **extra, **shown}
    if phase == "done" and last:
        return {**last, **extra, "phase": "done", "status": outcome}
    return base


def _screen_status(config: Any, phase: str, outcome: str | None) -> dict[str, Any]:
    done = phase == "done"
    return {
        "phase": SHOWN_AS.get(phase, "instructions"),
        "turn": "participant",
        "robot_doing": "",
        "message": f"the run has ended ({outcome})" if done else PHASE_MESSAGES.get(phase, ""),
        "instructions": config.instructions,
        "legs_delivered": 0,
        "legs_total": None,
        "gestures": 0,
        "actions": 0,
        "rejected": 0,
        "sim_time": 0.0,
        "system": config.system,
        "participant": config.participant,
        "session": config.session,
        "block": config.block,
        "policy": None,
        "status": outcome if done else "running",
        "starting": phase == "starting",
    }
