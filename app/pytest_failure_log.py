"""The event log of a failed test, in its pytest report (part of the ``motionsim`` plugin).

The fixtures :func:`watch` each controller a test uses (or every controller of a service the
test has to itself); when the test's call fails, each watched controller's whole event log is
written as JSON Lines into a temporary folder of the session, and its last
:data:`REPORT_TAIL` events with that file's path become a report section
``motionsim events: ID`` — shown under the failure, like captured output.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

#: Events shown in the report of a failed test (the whole log goes to a file).
REPORT_TAIL = 40
_WATCHED = pytest.StashKey[list[tuple[Any, "str | None"]]]()
_LOG_DIR = pytest.StashKey[Callable[[], Path]]()


def watch(request: pytest.FixtureRequest, client: Any, id: str | None) -> None:
    """Attach controller ``id`` (None: every controller of the client's service) to the
    report of the running test should it fail."""
    request.node.stash.setdefault(_WATCHED, []).append((client, id))
    factory = request.getfixturevalue("tmp_path_factory")
    request.node.stash[_LOG_DIR] = lambda: factory.mktemp("motionsim-events", numbered=True)


@pytest.hookimpl(wrapper=True, tryfirst=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Any:
    report = yield
    watched = item.stash.get(_WATCHED, None)
    if report.when == "call" and report.failed and watched:
        for title, text in _event_sections(watched, item.stash[_LOG_DIR]):
            report.sections.append((title, text))
    return report


def _event_sections(watched: list[tuple[Any, str | None]],
                    log_dir: Callable[[], Path]) -> Iterator[tuple[str, str]]:
    """Per watched controller: the last events and where the whole log was written."""
    folder: Path | None = None
    for client, only in watched:
        try:
            ids = [only] if only is not None else [c["id"] for c in client.controllers()]
            for id in ids:
                events = client.all_events(id)
                folder = folder or log_dir()
                path = folder / f"{id}.jsonl"
                path.write_text("".join(json.dumps(e) + "\n" for e in events), encoding="utf-8")
                tail = [json.dumps(e) for e in events[-REPORT_TAIL:]]
                yield (f"motionsim events: {id} (last {len(tail)} of {len(events)})",
                       "\n".join([*tail, f"whole log: {path}"]))
        except Exception as exc:  # the service may be gone; the failure itself still shows
            yield ("motionsim events", f"could not read the event log: {exc}")


__all__ = ["REPORT_TAIL", "pytest_runtest_makereport", "watch"]
