"""Reading a scenario file: YAML with the line number of every mapping key and list item.

Validation errors must name the field *and* the line of the file it came from, so the YAML is
composed into PyYAML's node tree (which keeps marks) and walked once to record, for each path
of keys / indices, the 1-based line where it starts.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import yaml

from .errors import ScenarioError

Path_ = tuple[Any, ...]

#: Last element of a path whose line is where a block scalar's text (``text: |``) begins, so
#: an error inside embedded program text (a PLC) can name the file line of the bad line.
VALUE_LINE = "<value line>"


def load_yaml(text: str, filename: str = "<scenario>") -> tuple[Any, dict[Path_, int]]:
    """Parse ``text``; return the data and ``{path: line}`` (path ``()`` is the document)."""
    try:
        loader = yaml.SafeLoader(text)
    except yaml.YAMLError as exc:  # a character YAML does not allow (the reader checks first)
        raise ScenarioError(f"not valid YAML: {exc}", file=filename) from None
    try:
        node = loader.get_single_node()
        if node is None:
            return None, {(): 1}
        data = loader.construct_document(node)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark else None
        raise ScenarioError(
            f"not valid YAML: {exc.problem or exc}", file=filename, line=line
        ) from None
    except yaml.YAMLError as exc:  # e.g. a control character met while scanning
        raise ScenarioError(f"not valid YAML: {exc}", file=filename) from None
    finally:
        loader.dispose()
    lines: dict[Path_, int] = {}
    _walk(loader, node, (), lines)
    return data, lines


def _walk(loader: yaml.SafeLoader, node: yaml.Node, path: Path_, out: dict[Path_, int]) -> None:
    out.setdefault(path, node.start_mark.line + 1)
    if isinstance(node, yaml.ScalarNode) and node.style in ("|", ">"):
        out[(*path, VALUE_LINE)] = node.start_mark.line + 2  # the line after the indicator
    if isinstance(node, yaml.MappingNode):
        for key_node, value_node in node.value:
            key = loader.construct_object(key_node, deep=True)
            if isinstance(key, list):  # unhashable keys cannot be fields anyway
                continue
            out[(*path, key)] = key_node.start_mark.line + 1
            _walk(loader, value_node, (*path, key), out)
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            out[(*path, i)] = item.start_mark.line + 1
            _walk(loader, item, (*path, i), out)


def locate(data: Any, loc: Sequence[Any], lines: dict[Path_, int]) -> tuple[Path_, int | None]:
    """The data path of a validation ``loc`` and the line where it (or its parent) starts.

    Pydantic puts union tags (the ``type`` of a host, the ``kind`` of an injected fault) and
    validator names in ``loc``; only the elements that are keys / indices of ``data`` are kept,
    plus a final unknown or missing key.
    """
    path: list[Any] = []
    cur = data
    for part in loc:
        if isinstance(cur, dict) and part in cur:
            path.append(part)
            cur = cur[part]
        elif isinstance(cur, dict) and str(part).isdigit() and int(part) in cur:
            path.append(int(part))
            cur = cur[int(part)]
        elif isinstance(cur, list) and isinstance(part, int) and 0 <= part < len(cur):
            path.append(part)
            cur = cur[part]
        elif isinstance(part, str) and (
            "[" in part or "-" in part
            or (isinstance(cur, dict) and part in (cur.get("type"), cur.get("kind")))
        ):
            continue  # a union tag (a host's ``type``, a fault's ``kind``) or a validator's name
        else:
            path.append(part)  # a field that is not in the file (unknown or missing)
            break
    tpath = tuple(path)
    for n in range(len(tpath), -1, -1):
        if tpath[:n] in lines:
            return tpath, lines[tpath[:n]]
    return tpath, None


def read_text(path: str | Path, base_dir: Path | None = None) -> tuple[str, Path]:
    """The text of a file named in a scenario, relative to the scenario's folder."""
    p = Path(path)
    if not p.is_absolute() and base_dir is not None:
        p = base_dir / p
    return p.read_text(encoding="utf-8"), p


def value_line(lines: dict[Path_, int], path: Path_) -> int | None:
    """The file line where the text of the scalar at ``path`` begins (its key's line for a
    one-line value, the line after ``|`` / ``>`` for a block)."""
    return lines.get((*path, VALUE_LINE), lines.get(path))


__all__ = ["VALUE_LINE", "load_yaml", "locate", "read_text", "value_line"]
