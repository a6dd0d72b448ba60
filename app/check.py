"""``motionsim check``: what a fresh card would refuse in a program file, without a card.

Each file is loaded into a new simulated controller of the chosen kind, through the same
public interfaces the service uses — nothing here parses a command:

* **PMAC** (``.pmc``, ``.pmac``, ``.pma``, ``.plc`` ...): every line goes to the card's
  terminal (:meth:`Controller.terminal`), as a host downloading the file would send it, and
  is answered in the card's background cycle on a virtual clock. A line answered ``ERRnnn``
  is an error (``FILE:LINE:COLUMN: ERRnnn meaning``); one the card would accept but
  motionsim does not simulate (the reply's ``not_simulated`` detail) is a warning. A file that
  uses ``#define`` / ``#include`` is expanded first by Diamond's preprocessor
  (``dls_pmaclib.dls_pmcpreprocessor``), whose line markers map each expanded line back to
  its file and line.
* **Trio** (``.bas``; ``.bal`` BASIC libraries): the program is parsed and compiled as
  ``PUT /programs/{name}`` does (:meth:`TrioController.check_program`), and every error is
  reported: a line that does not parse or compile is left out and the rest still checked. A
  keyword motionsim does not simulate is a warning. What the program needs is stored first:
  each ``INCLUDE "NAME"`` is satisfied by a file ``NAME.bas`` given on the same command line
  or found in a ``-I DIR`` folder, and the ``.bal`` libraries given or found there make their
  FUNCTIONs known.

Findings are :class:`Finding` records, printed as ``FILE:LINE:COLUMN: severity: message`` or
as JSON (``--format json``) for CI annotations.
"""

from __future__ import annotations

import contextlib
import re
from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

from ..sim.errors import MotionSimError, NotSimulated

#: File suffixes read as Trio BASIC; anything else is PMAC text unless ``--kind`` says.
TRIO_SUFFIXES = (".bas", ".txt.bas", ".bal")
#: Suffixes of the files an ``INCLUDE "NAME"`` may name (a program or a library).
_INCLUDABLE_SUFFIXES = (".bas", ".bal", ".txt")
_TRIO_INCLUDE = re.compile(r'^\s*INCLUDE\s*\(?\s*"([^"]+)"', re.I)
_PREPROCESSOR = re.compile(r"^#\s*(define|include)\b", re.I | re.M)
_MARKER = re.compile(r"^;#\* (.+) (\d+)$")
_COLUMN = re.compile(r"\(column (\d+)\)")
#: Simulated seconds a PMAC line may take to be answered (a background cycle is far shorter).
REPLY_WAIT_S = 1.0


@dataclass(frozen=True, slots=True)
class Finding:
    """One line the card refuses (``error``) or accepts without simulating it (``warning``)."""

    file: str
    line: int
    column: int
    severity: str
    code: str
    message: str
    text: str = ""

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}: {self.severity}: {self.code} {self.message}"

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True, slots=True)
class SourceLine:
    """A line as the card receives it, and where it came from."""

    file: str
    line: int
    text: str
    #: added to a column the card reports, to point into the file (leading blanks stripped)
    shift: int = 0
    expanded: bool = False


def kind_of(path: Path) -> str:
    """``trio`` for BASIC program files, else ``pmac``."""
    return "trio" if path.name.lower().endswith(TRIO_SUFFIXES) else "pmac"


def _new_controller(kind: str, model: str | None) -> Any:
    from .kinds import kind_class

    config: dict[str, Any] = {}
    if model is not None:
        if kind != "trio":
            raise ValueError(f"--model applies to trio controllers; {kind} has one model")
        config["model"] = model
    return kind_class(kind)("check", config)


# -- PMAC ------------------------------------------------------------------------------------


def pmac_source(path: Path, include: Sequence[Path] = ()) -> list[SourceLine]:
    """The lines a host would send for ``path``: as written, or expanded by the ``.pmc``
    preprocessor when the file uses ``#define`` / ``#include``."""
    text = path.read_text(encoding="utf-8", errors="replace")
    if not _PREPROCESSOR.search(text):
        return [SourceLine(str(path), n, line) for n, line in enumerate(text.splitlines(), 1)]
    try:
        from dls_pmaclib.dls_pmcpreprocessor import ClsPmacParser
    except ImportError:
        raise ValueError(f"{path} uses #define/#include: the .pmc preprocessor is needed "
                         "(pip install dls-pmaclib)") from None
    import logging

    quiet = logging.getLogger("dls_pmaclib")  # a missing include is our finding, not its log
    level, quiet.level = quiet.level, logging.ERROR
    try:
        expanded = ClsPmacParser([str(p) for p in include]).parse(str(path), debug=True) or []
    finally:
        quiet.setLevel(level)
    return list(_mapped(expanded, path))


_INCLUDE = re.compile(r"^#(?:include|INCLUDE)\b\s*(.*?)\s*$")


def missing_includes(path: Path, include: Sequence[Path] = (),
                     seen: set[Path] | None = None) -> list[Finding]:
    """``#include`` lines whose file is in none of the folders the preprocessor searches
    (the including file's folder, then ``include``): it leaves them out without a word, so
    they are errors here, at their line."""
    seen = seen if seen is not None else set()
    if path.resolve() in seen:
        return []
    seen.add(path.resolve())
    found: list[Finding] = []
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    for n, line in enumerate(lines, 1):
        m = _INCLUDE.match(line.split(";")[0])
        if not m:
            continue
        name = m[1].strip(' "\r')
        folders = [path.parent, *include]
        target = next((f / name for f in folders if (f / name).exists()), None)
        if target is None:
            found.append(Finding(str(path), n, line.find(name) + 1, "error", "include",
                                 f"cannot find {name!r} (searched "
                                 f"{', '.join(str(f) for f in folders)}; -I DIR adds a folder)",
                                 line))
        else:
            found += missing_includes(target, include, seen)
    return found


def _mapped(expanded: list[str], top: Path) -> Iterator[SourceLine]:
    """Expanded lines, each with the file and line its ``;#* FILE LINE`` marker names."""
    originals: dict[str, list[str]] = {}
    where: tuple[str, int] = (str(top), 0)
    for out in expanded:
        marker = _MARKER.match(out)
        if marker:
            where = (marker[1], int(marker[2]))
            continue
        file, n = where
        if file not in originals:
            originals[file] = Path(file).read_text(errors="replace").splitlines()
        lines = originals[file]
        original = lines[n - 1].split(";")[0] if 0 < n <= len(lines) else out
        shown = _display_name(file, top)
        stripped = original.strip("\r\n\t")
        if out == stripped:
            yield SourceLine(shown, n, out, shift=len(original) - len(original.lstrip("\r\n\t")))
        else:
            yield SourceLine(shown, n, out, expanded=True)


def _display_name(file: str, top: Path) -> str:
    """An included file's path as the user would write it (relative to the top file's folder
    when it lies below it)."""
    path = Path(file)
    if path.resolve() == top.resolve():
        return str(top)
    try:
        return str(top.parent / path.resolve().relative_to(top.parent.resolve()))
    except ValueError:
        return file


def check_pmac(lines: Sequence[SourceLine], ctl: Any) -> list[Finding]:
    """Send each line to ``ctl``'s terminal and collect what it refuses."""
    from ..sim.pmac.card.error_codes import meaning
    from .clock import VirtualClock

    clock = VirtualClock(ctl.env)
    found: list[Finding] = []
    for src in lines:
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
        found.append(Finding(src.file, src.line, column, "error", reply.error, text + note,
                             src.text))
    return found


# -- Trio ------------------------------------------------------------------------------------


def _program_name(path: Path) -> str:
    return re.sub(r"[^A-Za-z0-9_]", "_", path.name.split(".")[0])[:14].upper() or "CHECK"


def _find_included(name: str, siblings: Sequence[Path], include: Sequence[Path]
                   ) -> Path | None:
    """The file an ``INCLUDE "NAME"`` names: given on the command line, else in a ``-I``
    folder (``NAME.bas`` / ``.bal`` / ``.txt``, any case)."""
    for p in siblings:
        if _program_name(p) == name:
            return p
    for folder in include:
        if folder.is_dir():
            for p in sorted(folder.iterdir()):
                if p.suffix.lower() in _INCLUDABLE_SUFFIXES and _program_name(p) == name:
                    return p
    return None


def _libraries(siblings: Sequence[Path], include: Sequence[Path]) -> list[Path]:
    found = [p for p in siblings if p.suffix.lower() == ".bal"]
    for folder in include:
        if folder.is_dir():
            found += [p for p in sorted(folder.iterdir()) if p.suffix.lower() == ".bal"]
    return found


def _store_needed(path: Path, lines: Sequence[str], ctl: Any, siblings: Sequence[Path],
                  include: Sequence[Path]) -> list[Finding]:
    """Store what the program uses before it is checked: the BASIC libraries, then each
    INCLUDEd program; an INCLUDEd file that does not compile is an error at its INCLUDE."""
    me = path.resolve()
    for lib in _libraries(siblings, include):
        if lib.resolve() != me:  # a broken one defines nothing; checked on its own if given
            with contextlib.suppress(MotionSimError):
                ctl.store_program(_program_name(lib), lib.read_text(errors="replace") or "'")
    found: list[Finding] = []
    for n, line in enumerate(lines, 1):
        m = _TRIO_INCLUDE.match(line)
        if not m:
            continue
        name = m[1].upper()
        target = _find_included(name, siblings, include)
        if target is None or target.resolve() == me:
            continue  # the compile reports it, with the hint below
        try:
            ctl.store_program(name, target.read_text(errors="replace") or "'")
        except MotionSimError as exc:
            found.append(Finding(str(path), n, m.start(1) + 1, "error", exc.code,
                                 f'INCLUDE "{name}": {target} does not compile (line '
                                 f'{exc.details.get("line")}: {exc.message})', line))
    return found


def check_trio(path: Path, ctl: Any, siblings: Sequence[Path] = (),
               include: Sequence[Path] = ()) -> list[Finding]:
    """Every error compiling the program as ``PUT /programs/{name}`` does would meet
    (:meth:`TrioController.check_program`), after storing what it INCLUDEs and the libraries;
    not-simulated keywords are warnings."""
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    found = _store_needed(path, lines, ctl, siblings, include)
    name = _program_name(path)
    for exc in ctl.check_program(name, "\n".join(lines) or "'"):
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


# -- files -----------------------------------------------------------------------------------


def check_file(path: Path, kind: str | None = None, model: str | None = None,
               include: Sequence[Path] = (), siblings: Sequence[Path] = ()) -> list[Finding]:
    """Everything a fresh card of ``kind`` (default: from the suffix) finds in ``path``
    (``siblings``: the other files of the same check, a Trio program's INCLUDEs and
    libraries among them)."""
    kind = kind or kind_of(path)
    ctl = _new_controller(kind, model)
    if kind == "trio":
        return check_trio(path, ctl, siblings, include)
    missing = missing_includes(path, include)
    return missing + check_pmac(pmac_source(path, include), ctl)


__all__ = ["Finding", "SourceLine", "check_file", "check_pmac", "check_trio", "kind_of",
           "pmac_source"]
