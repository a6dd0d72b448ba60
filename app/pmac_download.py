"""What a host's downloader sends a Turbo PMAC for a program file: the preprocessing
conventions of the downloaders real program trees are written for, as one table.

A PMAC downloader reads the file as **bytes**: the card's command text is ASCII, and
comments — which the downloader strips before sending — may hold anything (Windows-1252 or
Shift-JIS remarks in lab files). Here a file is read as bytes and decoded byte for byte
(Latin-1, so a column is a byte offset and nothing can fail to decode); a byte above 0x7F
left in the command text after the comments are gone is an ``encoding`` error at its line and
column, and that line is not sent. None of the comment markers (``;``, ``//``, ``/*``) nor
``"`` can be the second byte of a Shift-JIS or UTF-8 character, so reading the bytes one by
one never mistakes a multi-byte character for a marker.

The conventions (:data:`DIALECTS`, ``motionsim check --dialect``):

``diamond``
    Diamond's ``.pmc`` preprocessor (``dls_pmaclib.dls_pmcpreprocessor.ClsPmacParser``,
    what their EPICS builds and tools run; ``tests/app/test_check.py`` compares the two line
    for line): ``;`` starts a comment; ``#define NAME text`` / ``#DEFINE`` (those two
    spellings only) define a macro, its text expanded by the macros defined before it;
    ``#include "file"`` / ``#INCLUDE`` insert a file (the name may be bare; ``<file>`` is not
    understood); a line is expanded by plain text replacement, longest macro name first —
    inside words too, as that tool does.
``pewin``
    Delta Tau's PEWIN32 / PEWIN32PRO editor and PComm32 download. ``[INF]`` (no page of the
    PEWIN or PComm32 manual was reachable; these are the conventions their users' files are
    written in): ``;`` and ``//`` start a comment, ``/* ... */`` is a comment that may span
    lines; directives in any case (``#define``, ``#Define``, ``#DEFINE``, ``#include``) with
    blanks allowed after ``#``; ``#include "file"`` and ``#include <file>`` (C's two forms);
    ``#ifdef`` / ``#ifndef`` / ``#else`` / ``#endif`` / ``#undef`` as in C (a line in a block
    not taken is neither sent nor checked); a macro replaces whole names only (``AX`` does not
    change ``MAX``), as a C preprocessor does.
``msi``
    EPICS ``msi`` substitution, run on templates before download: ``$(NAME)`` and
    ``${NAME}`` (``$(NAME=default)`` with a default) take their value from ``-D NAME=value``
    or an ``msi`` ``substitute "NAME=value,..."`` line; ``include "file"`` inserts a file.
    A macro no value is given for is an error naming it, at its line and column (``msi``
    itself only warns and leaves the text, which the card then refuses). The expanded text
    then goes through Diamond's directives, as a build that runs ``msi`` on a ``.pmc``
    template does.

``auto`` (the default) picks per download — a file and the files it includes — in
:func:`detect`: ``msi`` when ``$(`` or ``${`` appears in the command text, else ``pewin`` when
one of them uses a ``//`` or ``/*`` comment, ``#include <...>``, ``#ifdef`` or a directive
spelled other than Diamond's, else ``diamond`` (which, for a file without directives, sends
each line as written minus its comment).

An ``#include`` is searched for beside the including file, then in each ``-I DIR`` in turn; a
missing one is an ``include`` error at its line and column, and every refusal after it is
counted under it (see :mod:`motionsim.app.check`).
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Final, Literal


@dataclass(frozen=True, slots=True)
class SourceLine:
    """A line as the card receives it, and where it came from."""

    file: str
    line: int
    text: str
    #: added to a column the card reports, to point into the file (leading blanks stripped)
    shift: int = 0
    expanded: bool = False
    #: why refusals of this line follow from an earlier failure ("" when they do not)
    cause: str = ""


@dataclass(frozen=True, slots=True)
class Problem:
    """What the downloader itself finds before the card sees a line."""

    file: str
    line: int
    column: int
    code: Literal["encoding", "include", "macro", "directive"]
    message: str
    text: str = ""
    cause: str = ""


Substitution = Literal["text", "names", "msi"]


@dataclass(frozen=True, slots=True)
class Dialect:
    """One downloader's preprocessing conventions (a row of :data:`DIALECTS`)."""

    name: str
    #: markers that start a comment running to the end of the line
    line_comments: tuple[str, ...]
    #: ``/* ... */`` comments (may span lines)
    block_comments: bool
    #: a ``#define`` line: group ``name``, group ``text``
    define: re.Pattern[str]
    #: an ``#include`` line: group ``file``
    include: re.Pattern[str]
    #: how defined macros replace text
    substitution: Substitution
    #: ``msi`` ``$(NAME)`` expansion before the directives
    msi: bool = False
    #: ``#ifdef`` / ``#ifndef`` / ``#else`` / ``#endif`` / ``#undef``
    conditionals: bool = False
    what: str = ""


_DIAMOND_DEFINE = re.compile(r"^#(?:define|DEFINE)\b[ \t]*(?P<name>\S+)[ \t]+(?P<text>.*?)\s*$")
_DIAMOND_INCLUDE = re.compile(r'^#(?:include|INCLUDE)\b(?P<file>.*)$')
_PEWIN_DEFINE = re.compile(r"^\s*#\s*define\b[ \t]*(?P<name>\S+)(?:[ \t]+(?P<text>.*?))?\s*$",
                           re.I)
_PEWIN_INCLUDE = re.compile(r'^\s*#\s*include\b(?P<file>.*)$', re.I)

#: The conventions ``--dialect`` names, one row each (the module docstring says what each does).
DIALECTS: Final[dict[str, Dialect]] = {d.name: d for d in (
    Dialect("diamond", (";",), False, _DIAMOND_DEFINE, _DIAMOND_INCLUDE, "text",
            what="Diamond's .pmc preprocessor (dls-pmaclib): ; comments, #define/#DEFINE, "
                 "#include \"file\", plain text replacement"),
    Dialect("pewin", (";", "//"), True, _PEWIN_DEFINE, _PEWIN_INCLUDE, "names",
            conditionals=True,
            what="PEWIN32 / PComm32: ; // /* */ comments, #define in any case, "
                 "#include \"file\" or <file>, #ifdef/#ifndef/#else/#endif/#undef, "
                 "whole-name replacement"),
    Dialect("msi", (";",), False, _DIAMOND_DEFINE, _DIAMOND_INCLUDE, "text", msi=True,
            what="EPICS msi: $(NAME) ${NAME} from -D NAME=value, include \"file\", "
                 "then Diamond's directives"),
)}
DIALECT_NAMES: Final = ("auto", *DIALECTS)

_MSI_REF = re.compile(r"\$(?:\((?P<p>[^)=]*)(?:=(?P<pd>[^)]*))?\)"
                      r"|\{(?P<b>[^}=]*)(?:=(?P<bd>[^}]*))?\})")
_MSI_INCLUDE = re.compile(r'^\s*include\s+"(?P<file>[^"]+)"\s*$')
_MSI_SUBSTITUTE = re.compile(r'^\s*substitute\s+"(?P<pairs>[^"]*)"\s*$')
_CONDITIONAL = re.compile(
    r"^\s*#\s*(?P<word>ifdef|ifndef|else|endif|undef)\b[ \t]*(?P<name>[^ \t]*)", re.I)
_NON_ASCII = re.compile(r"[^\x00-\x7f]")
#: The cause ``encoding`` problems are counted under (one file in another encoding has many).
NON_ASCII_CAUSE: Final = "they hold bytes above 0x7F outside a comment"


def read_lines(path: Path) -> list[str]:
    """The file's lines, byte for byte (Latin-1: one character per byte, never an error),
    without their line ends (CR LF, LF or CR only: ``str.splitlines`` would also break at
    0x85, Windows-1252's ``…``, and at form feeds)."""
    text = path.read_bytes().decode("latin-1").replace("\r\n", "\n").replace("\r", "\n")
    lines = text.split("\n")
    return lines[:-1] if text.endswith("\n") or not text else lines


def detect(lines: Sequence[str]) -> Dialect:
    """The convention a file is written in, for ``--dialect auto`` (module docstring)."""
    pewin = False
    for line in lines:
        code = line.split(";")[0]
        if "$(" in code or "${" in code:
            return DIALECTS["msi"]
        include = _PEWIN_INCLUDE.match(code)
        directive = include or _PEWIN_DEFINE.match(code)
        diamonds = _DIAMOND_DEFINE.match(code) or _DIAMOND_INCLUDE.match(code)
        if "//" in code or "/*" in code or (include and "<" in code) or (
                directive and not diamonds) or _CONDITIONAL.match(code):
            pewin = True
    return DIALECTS["pewin" if pewin else "diamond"]


@dataclass
class _State:
    """What one download run carries from file to file: macros, -I folders, files open."""

    dialect: Dialect
    include: Sequence[Path]
    defines: dict[str, str]
    msi_values: dict[str, str]
    stack: list[Path] = field(default_factory=list)
    cause: str = ""
    included: set[Path] = field(default_factory=set)
    _names: re.Pattern[str] | None = None

    def substitute(self, text: str) -> str:
        """``text`` with the defined macros replaced as the dialect replaces them."""
        if not self.defines:
            return text
        if self.dialect.substitution == "text":
            for name in sorted(self.defines, key=len, reverse=True):
                text = text.replace(name, self.defines[name])
            return text
        if self._names is None:
            alts = "|".join(map(re.escape, sorted(self.defines, key=len, reverse=True)))
            self._names = re.compile(rf"(?<![A-Za-z0-9_])(?:{alts})(?![A-Za-z0-9_])")
        return self._names.sub(lambda m: self.defines[m[0]], text)

    def define(self, name: str, text: str) -> None:
        self.defines[name] = self.substitute(text)
        self._names = None

    def undefine(self, name: str) -> None:
        self.defines.pop(name, None)
        self._names = None


def _download_lines(path: Path, include: Sequence[Path], seen: set[Path]) -> Iterator[str]:
    """The lines of ``path`` and of every file it names in an include line of any
    convention, found as :func:`_include` finds them (for :func:`detect`: a download has
    one convention, which its included files may show when the top file does not)."""
    seen.add(path.resolve())
    try:
        lines = read_lines(path)
    except OSError:
        return
    yield from lines
    for line in lines:
        code = line.split(";")[0].split("//")[0]
        m = _PEWIN_INCLUDE.match(code) or _MSI_INCLUDE.match(code)
        if not m:
            continue
        name = m["file"].strip(' "\t<>')
        for folder in (path.parent, *include):
            target = folder / name
            if name and target.is_file():
                if target.resolve() not in seen:
                    yield from _download_lines(target, include, seen)
                break


def _start(path: Path, dialect: str, include: Sequence[Path],
           defines: Mapping[str, str] | None) -> tuple[list[str], _State]:
    lines = read_lines(path)
    row = (detect(list(_download_lines(path, include, set()))) if dialect == "auto"
           else DIALECTS[dialect])
    values = dict(defines or {})
    return lines, _State(row, include, {} if row.msi else dict(values),
                         values if row.msi else {})


def expand(path: Path, dialect: str = "auto", include: Sequence[Path] = (),
           defines: Mapping[str, str] | None = None) -> Iterator[SourceLine | Problem]:
    """The lines a downloader of ``dialect`` sends for ``path``, in order, and the problems it
    finds on the way (each where it occurs). ``defines`` are ``-D NAME=value``: predefined
    macros of ``diamond`` / ``pewin``, ``msi`` values."""
    lines, state = _start(path, dialect, include, defines)
    yield from _file(path, lines, state, path)


def included_files(path: Path, dialect: str = "auto", include: Sequence[Path] = (),
                   defines: Mapping[str, str] | None = None) -> set[Path]:
    """Every file ``path`` includes, directly or not (resolved paths)."""
    lines, state = _start(path, dialect, include, defines)
    for _ in _file(path, lines, state, path):
        pass
    return state.included


def _shown(file: Path, top: Path) -> str:
    """An included file's path as the user would write it (relative to the top file's folder
    when it lies below it)."""
    if file == top:
        return str(top)
    try:
        return str(top.parent / file.resolve().relative_to(top.parent.resolve()))
    except ValueError:
        return str(file)


def _strip_comments(line: str, row: Dialect, in_block: bool) -> tuple[str, bool]:
    """The command text of ``line`` (comments blanked, so columns stay), and whether a
    ``/*`` comment is still open at its end."""
    out: list[str] = []
    i, n = 0, len(line)
    while i < n:
        if in_block:
            end = line.find("*/", i)
            if end < 0:
                out.append(" " * (n - i))
                return "".join(out), True
            out.append(" " * (end + 2 - i))
            i, in_block = end + 2, False
            continue
        cut = n
        for marker in row.line_comments:
            at = line.find(marker, i)
            if 0 <= at < cut:
                cut = at
        block = line.find("/*", i) if row.block_comments else -1
        if 0 <= block < cut:
            out.append(line[i:block] + "  ")
            i, in_block = block + 2, True
            continue
        out.append(line[i:cut])
        break
    return "".join(out), in_block


def _file(path: Path, lines: list[str], state: _State, top: Path
          ) -> Iterator[SourceLine | Problem]:
    row = state.dialect
    shown = _shown(path, top)
    state.stack.append(path.resolve())
    in_block = False
    #: open #ifdef blocks: [taking lines, the condition, #else seen, line of the #ifdef]
    blocks: list[list[Any]] = []
    for n, original in enumerate(lines, 1):
        if row.block_comments or len(row.line_comments) > 1:
            code, in_block = _strip_comments(original, row, in_block)
        else:
            code = original.split(";")[0]
        if row.conditionals:
            cond = _CONDITIONAL.match(code)
            if cond:
                problem = _conditional(cond, blocks, state, shown, n, original)
                if problem:
                    yield problem
                continue
            if blocks and not blocks[-1][0]:
                continue  # inside an #ifdef not taken: not sent, not checked
        bad = _NON_ASCII.search(code)
        if bad:
            byte = ord(bad[0])
            yield Problem(shown, n, bad.start() + 1, "encoding",
                          f"byte 0x{byte:02X} is not ASCII: a PMAC's command text is ASCII "
                          "(only a comment may hold other bytes); the line is not sent",
                          original, NON_ASCII_CAUSE)
            continue
        if row.msi:
            if (sub := _MSI_SUBSTITUTE.match(code)):
                for pair in filter(None, (p.strip() for p in sub["pairs"].split(","))):
                    name, _, value = pair.partition("=")
                    state.msi_values[name.strip()] = value.strip()
                continue
            if (inc := _MSI_INCLUDE.match(code)):
                yield from _include(inc["file"], code.find(inc["file"]) + 1, path, n,
                                    original, state, top)
                continue
            expanded, problems = _msi_expand(code, state.msi_values, shown, n, original,
                                             state.cause)
            if problems:
                yield from problems
                continue
            code = expanded
        if not code.strip():
            continue
        directive = row.define.match(code)
        if directive:
            state.define(directive["name"], directive["text"] or "")
            continue
        inc = row.include.match(code)
        if inc:
            name = inc["file"].strip(' "\r\t')
            if row.name == "pewin" and name.startswith("<") and name.endswith(">"):
                name = name[1:-1].strip()
            yield from _include(name, code.find(name) + 1, path, n, original, state, top)
            continue
        sent = state.substitute(code)
        # Diamond's tool strips CR, LF and tabs at both ends of a line (not blanks)
        stripped = sent.strip("\r\n\t")
        if sent == code:
            yield SourceLine(shown, n, stripped, shift=len(sent) - len(sent.lstrip("\r\n\t")),
                             cause=state.cause)
        else:
            yield SourceLine(shown, n, stripped, expanded=True, cause=state.cause)
    for block in blocks:
        yield Problem(shown, block[3], 1, "directive", "#ifdef / #ifndef without its #endif",
                      lines[block[3] - 1])
    state.stack.pop()


def _conditional(m: re.Match[str], blocks: list[list[Any]], state: _State, shown: str,
                 n: int, original: str) -> Problem | None:
    """One ``#ifdef`` / ``#ifndef`` / ``#else`` / ``#endif`` / ``#undef`` line (``pewin``
    ``[INF]``, as a C preprocessor reads them): lines are taken while every enclosing block
    is taken; a misplaced ``#else`` / ``#endif`` is a ``directive`` problem."""
    word, name = m["word"].lower(), m["name"]
    outer = all(b[0] for b in blocks)
    if word in ("ifdef", "ifndef"):
        if not name:
            return Problem(shown, n, m.end() + 1, "directive", f"#{word} needs a macro name",
                           original)
        holds = (name in state.defines) == (word == "ifdef")
        blocks.append([outer and holds, holds, False, n])
    elif word == "undef":
        if outer:
            state.undefine(name)
    elif not blocks:
        return Problem(shown, n, 1, "directive", f"#{word} without #ifdef / #ifndef", original)
    elif word == "else":
        if blocks[-1][2]:
            return Problem(shown, n, 1, "directive", "a second #else in one #ifdef", original)
        enclosing = all(b[0] for b in blocks[:-1])
        blocks[-1][0], blocks[-1][2] = enclosing and not blocks[-1][1], True
    else:
        blocks.pop()
    return None


def _include(name: str, column: int, path: Path, n: int, original: str, state: _State,
             top: Path) -> Iterator[SourceLine | Problem]:
    # beside the including file, then beside each file that includes it (Diamond's tool
    # passes its folders down to nested includes), then each -I folder
    folders = list(dict.fromkeys([*(p.parent for p in reversed(state.stack)), *state.include]))
    target = next((f / name for f in folders if name and (f / name).is_file()), None)
    shown = _shown(path, top)
    if target is None:
        yield Problem(shown, n, max(column, 1), "include",
                      f"cannot find {name!r} (searched {', '.join(str(f) for f in folders)};"
                      " -I DIR adds a folder)", original, state.cause)
        state.cause = state.cause or f"the #include at {shown}:{n} was not found"
        return
    resolved = target.resolve()
    if resolved in state.stack:
        yield Problem(shown, n, max(column, 1), "include",
                      f"{name!r} includes itself (through "
                      f"{' -> '.join(p.name for p in state.stack)})",
                      original, state.cause)
        return
    state.included.add(resolved)
    try:
        lines = read_lines(target)
    except OSError as exc:
        yield Problem(shown, n, max(column, 1), "include", f"cannot read {name!r}: {exc}",
                      original, state.cause)
        return
    yield from _file(target, lines, state, top)


def _msi_expand(code: str, values: Mapping[str, str], shown: str, n: int, original: str,
                cause: str) -> tuple[str, list[Problem]]:
    """``code`` with its ``$(NAME)`` / ``${NAME}`` references replaced; an undefined one
    (no value, no default) is a problem naming it at its column."""
    problems: list[Problem] = []

    def one(m: re.Match[str]) -> str:
        name = (m["p"] if m["p"] is not None else m["b"]).strip()
        default = m["pd"] if m["p"] is not None else m["bd"]
        if name in values:
            return values[name]
        if default is not None:
            return default
        problems.append(Problem(shown, n, m.start() + 1, "macro",
                                f"{m[0]} is not defined (-D {name}=VALUE gives it a value)",
                                original, cause or f"{m[0]} is not defined"))
        return m[0]

    return _MSI_REF.sub(one, code), problems


__all__ = ["DIALECTS", "DIALECT_NAMES", "NON_ASCII_CAUSE", "Dialect", "Problem", "SourceLine",
           "detect", "expand", "included_files", "read_lines"]
