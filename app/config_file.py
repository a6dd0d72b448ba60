"""Reading ``motionsim serve --config FILE`` so that every mistake is one line naming its place.

A YAML or JSON syntax error becomes ``FILE:LINE:COLUMN: not valid YAML: what`` (the parser's
own mark, 1-based); a setting the service refuses becomes ``FILE:LINE: field: what``, the line
being where that field (or its nearest parent) is written. The file is composed into PyYAML's
node tree once to learn those lines (JSON is read by :mod:`json`, then by the same YAML
composer for the lines, as JSON's objects are YAML flow mappings).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import yaml

from .scenarios.errors import dotted
from .scenarios.source import locate

Lines = dict[tuple[Any, ...], int]


class ConfigFileError(ValueError):
    """A settings file that cannot be used; ``str()`` is the one line to print."""


def _yaml_lines(text: str) -> Lines:
    """``{path of keys / indices: 1-based line}`` of a document that parses."""
    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
        out: Lines = {}
        if node is not None:
            _walk(loader, node, (), out)
        return out
    finally:
        loader.dispose()


def _walk(loader: yaml.SafeLoader, node: yaml.Node, path: tuple[Any, ...], out: Lines) -> None:
    out.setdefault(path, node.start_mark.line + 1)
    if isinstance(node, yaml.MappingNode):
        for key_node, value_node in node.value:
            key = loader.construct_object(key_node, deep=True)
            if isinstance(key, str | int):
                out[(*path, key)] = key_node.start_mark.line + 1
                _walk(loader, value_node, (*path, key), out)
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            out[(*path, i)] = item.start_mark.line + 1
            _walk(loader, item, (*path, i), out)


def read_config(path: Path) -> tuple[dict[str, Any], Lines]:
    """The settings in ``path`` and the line of each; :class:`ConfigFileError` otherwise."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigFileError(f"{path}: cannot read: {exc}") from None
    if path.suffix.lower() == ".json":
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ConfigFileError(f"{path}:{exc.lineno}:{exc.colno}: not valid JSON: {exc.msg}"
                                  ) from None
    else:
        try:
            data = yaml.safe_load(text)
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            where = f"{path}:{mark.line + 1}:{mark.column + 1}" if mark else str(path)
            what = exc.problem or exc.context or "syntax error"
            raise ConfigFileError(f"{where}: not valid YAML: {what}") from None
        except yaml.YAMLError as exc:
            raise ConfigFileError(f"{path}: not valid YAML: {exc}") from None
    if data is None:
        return {}, {}
    if not isinstance(data, dict):
        raise ConfigFileError(f"{path}:1:1: expected a mapping of settings at the top level, "
                              f"got a {type(data).__name__}")
    try:
        lines = _yaml_lines(text)
    except yaml.YAMLError:  # JSON YAML does not read the same way: no lines, still valid
        lines = {}
    return data, lines


def where(path: Path, data: dict[str, Any], lines: Lines, loc: Sequence[Any]) -> str | None:
    """``FILE:LINE`` of the field at ``loc`` if it was written in the file, else None."""
    tpath, line = locate(data, loc, lines)
    return f"{path}:{line}" if line is not None and tpath[:1] and tpath[0] in data else None


__all__ = ["ConfigFileError", "dotted", "read_config", "where"]
