"""``motionsim check``: what a fresh card would refuse in a program file, without a card.

Each file is loaded into a new simulated controller of the chosen kind, through the same
public interfaces the service uses — nothing here parses a command:

* **PMAC** (``.pmc``, ``.pmac``, ``.pma``, ``.plc`` ...): the file is read as a downloader
  reads it (bytes; comments stripped, macros and includes expanded by the convention of
  ``--dialect``: :mod:`motionsim.app.pmac_download`), and every line goes to the card's
  terminal (:meth:`Controller.terminal`), as the downloader would send it, answered in the
  card's background cycle on a virtual clock. A line answered ``ERRnnn`` is an error
  (``FILE:LINE:COLUMN: ERRnnn meaning``); one the card would accept but motionsim does not
  simulate (the reply's ``not_simulated`` detail) is a warning.
* **Trio** (``.bas``): the program is stored (``store_program``), i.e. parsed and compiled as
  ``PUT /programs/{name}`` does. A keyword motionsim does not simulate is a warning (the line
  is then set aside and the program compiled again); the first compile error is the error,
  as the controller's own compiler reports one.

**Follow-on refusals are counted under their cause**, not listed: after a refused ``OPEN``
every line meant for that buffer is answered ERR005 (no buffer open) until the next
``CLOSE`` or a buffer opens; after a missing ``#include`` every refusal is suspect (its
macros and ``OPEN`` lines are missing); every use of an undefined ``msi`` macro is one
mistake. :func:`grouped` keeps the first such finding and counts the others
(``… and 1 299 more lines refused because OPEN at line 3 failed``): their verdicts are not
what the file would get once the cause is fixed.

Findings are :class:`Finding` records, printed as ``FILE:LINE:COLUMN: severity: message`` or
as JSON (``--format json``) for CI annotations. ``motionsim check DIR`` checks a whole tree in
one process (:func:`tree_files`).
"""

from __future__ import annotations

import contextlib
import functools
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

from ..sim.errors import MotionSimError, NotSimulated
from .pmac_download import (
    NON_ASCII_CAUSE,
    Problem,
    SourceLine,
    expand,
    included_files,
    read_lines,
)

#: File suffixes read as Trio BASIC; anything else is PMAC text unless ``--kind`` says.
TRIO_SUFFIXES = (".bas", ".txt.bas", ".bal")
#: Suffixes of the PMAC program files a folder is searched for (``check DIR``); named files
#: of any other suffix are PMAC text too.
PMAC_SUFFIXES = (".pmc", ".pmac", ".pma", ".plc")
_COLUMN = re.compile(r"\(column (\d+)\)")
#: Simulated seconds a PMAC line may take to be answered (a background cycle is far shorter).
REPLY_WAIT_S = 1.0
#: The card's answer to a buffer command with no buffer open (TSRM I6 error table).
NO_BUFFER_OPEN = "ERR005"


@dataclass(frozen=True, slots=True)
class Finding:
    """One line the card refuses (``error``) or accepts without simulating it (``warning``).

    ``cause`` names the earlier failure a follow-on refusal comes from ("" for none);
    ``more`` is how many further findings of the same cause :func:`grouped` counted here.
    """

    file: str
    line: int
    column: int
    severity: str
    code: str
    message: str
    text: str = ""
    cause: str = ""
    more: int = 0

    def __str__(self) -> str:
        out = f"{self.file}:{self.line}:{self.column}: {self.severity}: {self.code} {self.message}"
        if self.more:
            count = f"{self.more:,}".replace(",", " ")
            out += (f"\n  … and {count} more line{'s' if self.more > 1 else ''} refused "
                    f"because {self.cause}")
        return out

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def kind_of(path: Path) -> str:
    """``trio`` for BASIC program files, else ``pmac``."""
    return "trio" if path.name.lower().endswith(TRIO_SUFFIXES) else "pmac"


@functools.cache
def _controller_class(kind: str) -> Any:
    """The kind's class, looked up once per run (the entry-point scan reads every installed
    distribution's metadata: ~80 ms, more than checking a file)."""
    from .kinds import kind_class

    return kind_class(kind)


def _new_controller(kind: str, model: str | None) -> Any:
    """A fresh card of ``kind``; ``model`` is the Trio model, so a tree mixing PMAC and Trio
    files checks its PMAC files on the one Turbo PMAC whatever ``--model`` says."""
    config: dict[str, Any] = {}
    if model is not None and kind == "trio":
        config["model"] = model
    return _controller_class(kind)("check", config)


# -- PMAC ------------------------------------------------------------------------------------


def _has_word(text: str, name: str) -> bool:
    """Whether ``text`` holds the command word ``name`` (``OPEN``, ``CLOSE``), read by the
    card's own lexer and keyword table, so every spelling the card accepts counts."""
    from ..sim.pmac.language import keywords
    from ..sim.pmac.language.parser import tokenize

    if name not in text.upper():
        return False
    try:
        tokens = tokenize(text.upper())
    except MotionSimError:
        return False
    for kind, word, _start, _end in tokens:
        if kind == "word":
            row = keywords.lookup(word)
            if row is not None and row.name == name:
                return True
    return False


def _where(file: str, line: int, of: str) -> str:
    """``line 3`` in the same file as ``of``, else ``FILE:3``."""
    return f"line {line}" if file == of else f"{file}:{line}"


def check_pmac(items: Iterable[SourceLine | Problem], ctl: Any) -> list[Finding]:
    """Send each line to ``ctl``'s terminal and collect what it refuses, with the
    downloader's own problems where they occur; follow-on refusals carry their ``cause``."""
    from ..sim.pmac.card.error_codes import meaning
    from .clock import VirtualClock

    clock = VirtualClock(ctl.env)
    found: list[Finding] = []
    failed_open: tuple[str, int] | None = None  # the refused OPEN ERR005s follow from
    for src in items:
        if isinstance(src, Problem):
            found.append(Finding(src.file, src.line, src.column, "error", src.code,
                                 src.message, src.text, src.cause))
            continue
        if not src.text.strip():
            continue
        try:
            reply = ctl.terminal(src.text)
            clock.run_until_reply(reply, REPLY_WAIT_S)
        except MotionSimError as exc:  # e.g. the watchdog tripped: the card answers nothing
            found.append(Finding(src.file, src.line, 1, "error", exc.code, exc.message,
                                 src.text))
            break
        if reply.error is None:
            if failed_open and (_has_word(src.text, "OPEN") or _has_word(src.text, "CLOSE")):
                failed_open = None  # a buffer opened, or the failed one's CLOSE came
            continue
        kind, detail = reply.detail or ("", "")
        m = _COLUMN.search(detail)
        column = (int(m[1]) + src.shift) if m else 1 + src.shift
        note = " (after macro expansion)" if src.expanded else ""
        if kind == "not_simulated":
            found.append(Finding(src.file, src.line, column, "warning", "not_simulated",
                                 detail + note, src.text))
            continue
        text = meaning(reply.error) or reply.error
        if detail:
            text += f": {_COLUMN.sub('', detail).strip()}"
        cause = src.cause
        if failed_open and reply.error == NO_BUFFER_OPEN:
            cause = f"OPEN at {_where(*failed_open, src.file)} failed"
        found.append(Finding(src.file, src.line, column, "error", reply.error, text + note,
                             src.text, cause))
        if _has_word(src.text, "OPEN"):
            failed_open = (src.file, src.line)
    return found


# -- Trio ------------------------------------------------------------------------------------


def _trio_code_end(line: str) -> int:
    """Where a Trio BASIC line's comment starts (``'`` outside a string, or a ``REM``
    line), or its length."""
    if line.lstrip().upper().startswith("REM"):
        return len(line) - len(line.lstrip())
    quoted = False
    for i, ch in enumerate(line):
        if ch == '"':
            quoted = not quoted
        elif ch == "'" and not quoted:
            return i
    return len(line)


def _trio_lines(path: Path) -> tuple[list[str], list[Finding]]:
    """The program's lines as bytes read one by one (comment bytes above 0x7F made ``?``),
    and an ``encoding`` finding for each line with such a byte in its program text."""
    lines = read_lines(path)
    found: list[Finding] = []
    for n, line in enumerate(lines, 1):
        end = _trio_code_end(line)
        bad = re.search(r"[^\x00-\x7f]", line[:end])
        if bad:
            found.append(Finding(str(path), n, bad.start() + 1, "error", "encoding",
                                 f"byte 0x{ord(bad[0]):02X} is not ASCII: Trio BASIC program "
                                 "text is ASCII (only a comment may hold other bytes)", line,
                                 NON_ASCII_CAUSE))
        else:
            lines[n - 1] = line[:end] + re.sub(r"[^\x00-\x7f]", "?", line[end:])
    return lines, found


_TRIO_INCLUDE = re.compile(r'^\s*INCLUDE\s*\(?\s*"([^"]+)"', re.I)
#: Suffixes of the files an ``INCLUDE "NAME"`` may name (a program or a library).
_INCLUDABLE_SUFFIXES = (".bas", ".bal", ".txt")


def _program_name(path: Path) -> str:
    return re.sub(r"[^A-Za-z0-9_]", "_", path.name.split(".")[0])[:14].upper() or "CHECK"


def _trio_places(path: Path, siblings: Sequence[Path], include: Sequence[Path]
                 ) -> list[Path]:
    """Where a program's INCLUDEs and libraries are looked for, in order: the files given
    on the command line, the program's own folder (a Trio project is a folder of programs
    downloaded together, ``[BK]`` Motion Perfect's project download), the ``-I`` folders."""
    out = list(siblings)
    for folder in (path.parent, *include):
        if folder.is_dir():
            out += sorted(p for p in folder.iterdir() if p.is_file()
                          and p.suffix.lower() in _INCLUDABLE_SUFFIXES)
    return out


def _store_needed(path: Path, lines: Sequence[str], ctl: Any, places: Sequence[Path],
                  seen: set[Path]) -> list[Finding]:
    """Store what the program uses before it is checked: the BASIC libraries (``.bal``),
    then each INCLUDEd program, theirs before them; an INCLUDEd file that does not compile
    is an error at its INCLUDE."""
    for lib in places:
        if lib.suffix.lower() == ".bal" and lib.resolve() not in seen:
            seen.add(lib.resolve())
            text, problems = _trio_lines(lib)
            if not problems:  # a broken one defines nothing; checked on its own if given
                with contextlib.suppress(MotionSimError):
                    ctl.store_program(_program_name(lib), "\n".join(text) or "'")
    found: list[Finding] = []
    for n, line in enumerate(lines, 1):
        m = _TRIO_INCLUDE.match(line)
        if not m:
            continue
        name = m[1].upper()
        target = next((p for p in places if _program_name(p) == name), None)
        if target is None or target.resolve() in seen:
            continue  # the compile reports a missing one, with the hint below
        seen.add(target.resolve())
        text, problems = _trio_lines(target)
        found += _store_needed(target, text, ctl, places, seen) if not problems else []
        try:
            ctl.store_program(name, "\n".join(text) or "'")
        except MotionSimError as exc:
            found.append(Finding(str(path), n, m.start(1) + 1, "error", exc.code,
                                 f'INCLUDE "{name}": {target} does not compile (line '
                                 f'{exc.details.get("line")}: {exc.message})', line))
    return found


def check_trio(path: Path, ctl: Any, siblings: Sequence[Path] = (),
               include: Sequence[Path] = ()) -> list[Finding]:
    """Every error compiling the program as ``PUT /programs/{name}`` does would meet
    (:meth:`TrioController.check_program`: a line that does not parse or compile is left out
    and the rest still checked), after storing the libraries and what it INCLUDEs;
    not-simulated keywords are warnings. The file is read as bytes: a byte above 0x7F in a
    comment is harmless, one in the program text an ``encoding`` error at its line and
    column (``[INF]`` the controller's program text is ASCII); a file with one is not
    compiled."""
    lines, found = _trio_lines(path)
    if found:
        return found
    found = _store_needed(path, lines, ctl, _trio_places(path, siblings, include),
                          {path.resolve()})
    for exc in ctl.check_program(_program_name(path), "\n".join(lines) or "'"):
        severity = "warning" if isinstance(exc, NotSimulated) else "error"
        finding = _trio_finding(path, exc, severity, lines)
        if "there is no program" in finding.message:
            missing = finding.message.rsplit(" ", 1)[-1]
            finding = replace(finding, message=finding.message + f" (give {missing}.bas on the "
                              "command line, or its folder with -I DIR)")
        found.append(finding)
    return found


def _trio_finding(path: Path, exc: MotionSimError, severity: str,
                  lines: Sequence[str]) -> Finding:
    n = int(exc.details.get("line") or 1)
    text = exc.details.get("text")
    if not isinstance(text, str):
        text = lines[n - 1] if 0 < n <= len(lines) else ""
    return Finding(str(path), n, int(exc.details.get("column") or 1), severity, exc.code,
                   exc.message, text)


# -- files and trees -------------------------------------------------------------------------


def check_file(path: Path, kind: str | None = None, model: str | None = None,
               include: Sequence[Path] = (), dialect: str = "auto",
               defines: Mapping[str, str] | None = None,
               siblings: Sequence[Path] = ()) -> list[Finding]:
    """Everything a fresh card of ``kind`` (default: from the suffix) finds in ``path``
    (ungrouped: :func:`grouped` folds the follow-ons); ``siblings``: the other files of the
    run, where a Trio program's INCLUDEs and libraries are looked for first."""
    kind = kind or kind_of(path)
    ctl = _new_controller(kind, model)
    if kind == "trio":
        return check_trio(path, ctl, siblings, include)
    return check_pmac(expand(path, dialect, include, defines), ctl)


def _program_file(path: Path) -> bool:
    name = path.name.lower()
    return name.endswith(TRIO_SUFFIXES) or name.endswith(PMAC_SUFFIXES)


def tree_files(paths: Sequence[Path], include: Sequence[Path] = (), dialect: str = "auto",
               defines: Mapping[str, str] | None = None) -> list[Path]:
    """The files ``check`` loads for ``paths``: a named file as it is; a folder's PMAC and
    Trio program files (:data:`PMAC_SUFFIXES`, :data:`TRIO_SUFFIXES`; folders whose name
    starts with ``.`` skipped; a broken link is listed, to be reported), in name order,
    except those another file of the folder ``#include``s — they are checked where they are
    included, as they are downloaded."""
    out: list[Path] = []
    for path in paths:
        if not path.is_dir():
            out.append(path)
            continue
        found = sorted(p for p in path.rglob("*") if (p.is_file() or p.is_symlink())
                       and _program_file(p)
                       and not any(part.startswith(".") for part in
                                   p.relative_to(path).parts[:-1]))
        included: set[Path] = set()
        for p in found:
            if kind_of(p) == "pmac":
                with contextlib.suppress(OSError):  # reported when the file is checked
                    included |= included_files(p, dialect, include, defines)
        out += [p for p in found if p.resolve() not in included]
    return out


def grouped(findings: Sequence[Finding]) -> list[Finding]:
    """``findings`` with each cause's follow-ons folded into its first one (``more``)."""
    first: dict[tuple[str, str], int] = {}
    out: list[Finding] = []
    for f in findings:
        if not f.cause:
            out.append(f)
            continue
        key = (f.file, f.cause)
        if key in first:
            out[first[key]] = replace(out[first[key]], more=out[first[key]].more + 1)
        else:
            first[key] = len(out)
            out.append(f)
    return out


__all__ = ["PMAC_SUFFIXES", "TRIO_SUFFIXES", "Finding", "SourceLine", "check_file",
           "check_pmac", "check_trio", "grouped", "kind_of", "tree_files"]
