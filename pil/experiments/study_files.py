"""Reading the small YAML files of the studies beyond the paper (mapping changes, people)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import yaml

from pil.task.parts import resolve_scenario
from pil.task.scenario import Scenario, ScenarioError, find_scenario
from pil.task.yaml_files import load_yaml_text, read_small_text, yaml_problem


def read_study_file(
    path: str | Path, keys: Sequence[str], what: str
) -> tuple[Path, Mapping[str, Any], Scenario]:
    """The file's path, its top-level mapping (only ``keys`` allowed) and its base scenario
    (``scenario:``, a file relative to this one or a shipped scenario's name; default the
    shipped assembly); errors name the file."""
    path = find_scenario(path)
    try:
        raw = load_yaml_text(read_small_text(path))
    except yaml.YAMLError as error:
        raise ScenarioError(f"{path}: the {what}: {yaml_problem(error)}") from None
    except RecursionError:
        raise ScenarioError(f"{path}: nested too deeply to be a {what}") from None
    except OSError as error:
        raise ScenarioError(f"{path}: cannot read the {what}: {error.strerror}") from None
    except ValueError as error:  # not UTF-8, too large
        raise ScenarioError(f"{path}: cannot read the {what}: {error}") from None
    if not isinstance(raw, Mapping):
        raise ScenarioError(f"{path}: expected a mapping with keys {', '.join(keys)}")
    for key in raw:
        if key not in keys:
            raise ScenarioError(f"{path}: unknown key {key!r}; valid choices: {', '.join(keys)}")
    base = raw.get("scenario")
    if base is None:
        return path, raw, resolve_scenario(None, {})
    target = path.parent / str(base)
    scenario = resolve_scenario(target if target.exists() else str(base), {})
    return path, raw, scenario
