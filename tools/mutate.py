"""``make mutate``: mutation testing of the decision modules, mutants made by cosmic-ray.

For each module of ``tools/mutation.toml`` (or those named on the command line) cosmic-ray
``init`` writes the mutants to a work DB in ``.mutation/``; this script then tests them itself
(``tools/mutation_fork.py``: a warm fork server, the mutant served from memory, the file on
disk never changed) and stores every result in that DB (``cr-report .mutation/<m>.sqlite``
reads it):

1. mutants inside type annotations or docstrings are equivalent by construction: stored as
   skipped, never run; so are the ``[[equivalent]]`` entries of ``mutation.toml``;
2. the module's test subset runs once under coverage with one context per test; a mutant then
   runs only the tests that execute its statement (``tools/mutation_lines.py``), the tests
   that killed the latest mutants first (neighbouring mutants of one function mostly fall to
   the same test), then fastest first, stopping at the first failure; a statement run at
   import time runs the whole subset; a statement no test executes survives without running;
3. each child has a time limit, never under 1.5x its tests' baseline time (a mutant that
   loops forever is killed; a slow survivor is not).

A DB whose module source is unchanged is resumed; ``--survivors`` re-tests only the survivors
(after new tests), ``--retest-with`` only with the given new test files, ``--timeouts`` the
mutants killed by their limit (under 3x it), ``--sample N`` a seeded sample of the pending
ones, ``--fresh`` starts over. Each module's results are also written to
``tools/mutation-results/<module>.json`` (committed: a fresh clone's ``--tally`` reports them;
a run on an unchanged source resumes from them, and one on an edited source carries over the
results of mutants whose function's code is unchanged). Prints killed / survived per module and
lists the survivors. A report, never a failure: the exit code is 0 unless the tooling itself
failed.

    python tools/mutate.py                      # every module
    python tools/mutate.py sim/pmac/buffers/rotary.py   # one
"""

from __future__ import annotations

import argparse
import contextlib
import difflib
import hashlib
import json
import os
import random
import signal
import subprocess
import sys
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import mutation_fork  # noqa: E402
from mutation_lines import (  # noqa: E402
    FunctionAnchors,
    StatementIndex,
    inert_reason,
    inert_spans,
    select,
)
from mutation_patch import changed_functions  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "tools" / "mutation.toml"
TIMEOUT_RETEST = 3.0  # --timeouts: a timed-out mutant's limit, times its first one
EQUIVALENTS = ROOT / "tools" / "mutation-equivalent"  # one <module stem>.toml a module
RESULTS = ROOT / "tools" / "mutation-results"  # one <module stem>.json a module, committed
WORK = ROOT / ".mutation"
PACKAGE = "motionsim"  # the repository's top-level folders are this package's subpackages
TARGET = 0.90
CR = str(Path(sys.executable).with_name("cosmic-ray"))  # beside this interpreter (the venv)
UNCOVERED = "no test in the subset executes this statement"
KILLERS = 4  # how many of the latest mutants' killing tests are tried first
INCOMPETENT_CODES = (4, 5, 70)  # pytest: usage error, no tests; the child itself broke
CARRIED = "carried; "  # prefix of the output of a result carried over from an earlier source


@dataclass
class Tally:
    module: str
    killed: int = 0
    survived: list[tuple[int, str, str, bool]] = field(default_factory=list)  # +uncovered
    equivalent: int = 0
    incompetent: int = 0
    seconds: float = 0.0
    ran: int = 0
    timing: dict = field(default_factory=dict)  # "patched" / "fresh": [mutants, seconds]
    untested: int | None = 0  # mutants not tested yet (None: no work DB at all)
    timeouts: int = 0  # of the killed: by their time limit
    carried: int = 0  # results carried over from an earlier version of the module
    stale: bool = False  # the DB was made from another version of the module's source

    @property
    def scored(self) -> int:
        return self.killed + len(self.survived)

    @property
    def rate(self) -> float:
        return self.killed / self.scored if self.scored else 1.0


def import_name(module: str) -> str:
    return ".".join([PACKAGE, *Path(module).with_suffix("").parts])


def _text_digest(source: str) -> str:
    return hashlib.sha256(source.encode()).hexdigest()


def _digest(module: str) -> str:
    return _text_digest((ROOT / module).read_text())


def _mutant(source: str, spec) -> str | None:
    """The source of the mutant ``spec`` names (None when cosmic-ray makes none)."""
    import cosmic_ray.plugins
    from cosmic_ray.mutating import mutate_code

    operator = cosmic_ray.plugins.get_operator(spec.operator_name)(**(spec.operator_args or {}))
    return mutate_code(source, operator, spec.occurrence)


def _init(module: str, stem: str, fresh: bool) -> Path:
    """The module's work DB: cosmic-ray's mutants of the current source (kept when the source
    is unchanged and not ``fresh``, so an interrupted run resumes)."""
    WORK.mkdir(exist_ok=True)
    cfg, db, stamp = WORK / f"{stem}.toml", WORK / f"{stem}.sqlite", WORK / f"{stem}.sha256"
    if not fresh and db.exists() and stamp.exists() and stamp.read_text() == _digest(module):
        return db
    cfg.write_text(
        "[cosmic-ray]\n"
        f'module-path = "{module}"\n'
        "timeout = 60\n"
        "excluded-modules = []\n"
        'test-command = "false"  # never run: tools/mutate.py tests the mutants\n'
        '\n[cosmic-ray.distributor]\nname = "local"\n'
    )
    db.unlink(missing_ok=True)
    subprocess.run([CR, "init", str(cfg), str(db)], cwd=ROOT, check=True)
    stamp.write_text(_digest(module))
    if not fresh:
        _import_results(module, stem, db, (ROOT / module).read_text())
    return db


def _result_row(spec, result) -> dict:
    """One mutant's result as a JSON row (the diff kept for survivors only: the report's)."""
    survived = result.test_outcome is not None and result.test_outcome.value == "survived"
    return {"operator": spec.operator_name, "occurrence": spec.occurrence,
            "line": spec.start_pos[0], "worker": result.worker_outcome.value,
            "test": result.test_outcome.value if result.test_outcome else None,
            "output": result.output, "diff": result.diff if survived else None}


def _carry_keys(items, source: str) -> dict[str, tuple]:
    """Each work item's key for carrying its result to another version of the module: its
    operator, its function's anchor (name, code digest) and its rank among that operator's
    mutants in that function (the same code gives the same mutants in the same order); none
    for code outside a function."""
    anchors = FunctionAnchors(source)
    groups: dict[tuple, list] = {}
    for item in items:
        (spec,) = item.mutations
        anchor = anchors.anchor(spec.start_pos[0])
        if anchor is not None:
            groups.setdefault((spec.operator_name, *anchor), []).append(item)
    keys = {}
    for group_key, group in groups.items():
        group.sort(key=lambda i: (tuple(i.mutations[0].start_pos), i.mutations[0].occurrence))
        for rank, item in enumerate(group):
            keys[item.job_id] = (*group_key, rank)
    return keys


def _export_results(module: str, db: Path, source: str) -> None:
    """The module's DB (made from ``source``) as ``tools/mutation-results/<stem>.json``, one
    mutant a line, each with its carry-over key."""
    from cosmic_ray.work_db import WorkDB, use_db

    with use_db(str(db), WorkDB.Mode.open) as work_db:
        keys = _carry_keys(list(work_db.work_items), source)
        rows = []
        for item, result in work_db.completed_work_items:
            row = _result_row(item.mutations[0], result)
            row["carry"] = keys.get(item.job_id)
            rows.append(row)
        total = work_db.num_work_items
    rows.sort(key=lambda r: (r["line"], r["operator"], r["occurrence"]))
    head = {"module": module, "source_sha256": _text_digest(source), "mutants": total,
            "spent": _spent(_stem(module))}
    body = ",\n".join(json.dumps(r, sort_keys=True) for r in rows)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"{_stem(module)}.json").write_text(
        json.dumps(head, sort_keys=True)[:-1] + ', "results": [\n' + body + "\n]}\n")


def _load_results(stem: str) -> dict | None:
    path = RESULTS / f"{stem}.json"
    return json.loads(path.read_text()) if path.exists() else None


def _import_results(module: str, stem: str, db: Path, source: str) -> None:
    """Fill a new DB with the committed results: all of them for the same source (mutants
    matched by operator and occurrence, time figures restored); for another version of the
    module, those of mutants whose function is unchanged (matched by their carry-over key,
    their output marked ``carried``; ``--fresh`` runs everything)."""
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import TestOutcome, WorkerOutcome, WorkResult

    data = _load_results(stem)
    if data is None:
        return
    same = data["source_sha256"] == _text_digest(source)
    if same:
        rows = {(r["operator"], r["occurrence"]): r for r in data["results"]}
    else:
        rows = {tuple(r["carry"]): r for r in data["results"] if r.get("carry")}
    with use_db(str(db), WorkDB.Mode.open) as work_db:
        items = list(work_db.pending_work_items)
        keys = {} if same else _carry_keys(items, source)
        for item in items:
            (spec,) = item.mutations
            key = (spec.operator_name, spec.occurrence) if same else keys.get(item.job_id)
            r = rows.get(key) if key is not None else None
            if r is None:
                continue
            output = r["output"]
            if not same and not (output or "").startswith(CARRIED):
                output = CARRIED + (output or "")
            work_db.set_result(item.job_id, WorkResult(
                worker_outcome=WorkerOutcome(r["worker"]), output=output,
                test_outcome=TestOutcome(r["test"]) if r["test"] else None, diff=r["diff"]))
    if same:
        (WORK / f"{stem}.spent.json").write_text(json.dumps(data["spent"]))


def _squash(text: str) -> str:
    return "".join(text.split())


def _equivalents(config: dict, module: str) -> dict[tuple[str, str], list[dict]]:
    """``[[equivalent]]`` entries of ``module`` by (operator, source line without spaces)."""
    out: dict[tuple[str, str], list[dict]] = {}
    for e in config.get("equivalent", []):
        if e["module"] == module:
            out.setdefault((e["operator"], _squash(e["code"])), []).append(e)
    return out


def _listed(equivalent: dict, operator: str, line: str, mutated_line: str,
            line_no: int) -> str | None:
    """The reason of the entry naming this mutant: its operator and source line, and, when
    the entry gives them, the mutated line (``mutant``) and the line number (``line``)."""
    for e in equivalent.get((operator, _squash(line)), []):
        if "mutant" in e and _squash(e["mutant"]) != _squash(mutated_line):
            continue
        if "line" in e and int(e["line"]) != line_no:
            continue
        return e["reason"]
    return None


def _diff(original: str, mutated: str, module: str) -> str:
    return "\n".join(difflib.unified_diff(original.splitlines(), mutated.splitlines(),
                                          f"a/{module}", f"b/{module}", lineterm=""))


def _limit(durations: dict[str, float], tests: list[str], overhead: float, cap: float) -> float:
    """A mutant's time limit: 3x its tests' baseline time (measured under coverage, so
    slower than the mutant's run) plus start-up, at most ``cap`` — but never under 1.5x the
    baseline time: a limit the unmutated tests could hit would count a slow survivor as
    killed (a timeout is a kill)."""
    start, tests_s = 10.0 + 2.0 * overhead, sum(durations[t] for t in tests)
    return max(min(cap, start + 3.0 * tests_s), start + 1.5 * tests_s)


def run_module(module: str, tests: list[str], config: dict, args) -> Tally:
    """Test every pending mutant of ``module`` (see the module docstring) and tally the DB."""
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import TestOutcome, WorkerOutcome, WorkResult

    stem = _stem(module)
    started = time.perf_counter()
    db = _init(module, stem, args.fresh)
    if args.fresh:
        (WORK / f"{stem}.spent.json").unlink(missing_ok=True)
    target = ROOT / module
    source = target.read_text()
    cov_file, log = WORK / f"{stem}.coverage.json", WORK / f"{stem}.baseline.log"
    base = mutation_fork.baseline(tests, target, cov_file, 1800.0, log)
    if base.code != 0:
        raise SystemExit(f"{module}: its test subset fails on the unmutated code "
                         f"(exit {base.code}); see {log}")
    measured = json.loads(cov_file.read_text())
    lines = {int(k): v for k, v in measured["lines"].items()}
    durations: dict[str, float] = measured["durations"]
    overhead = max(0.0, base.seconds - sum(durations.values()))
    by_speed = sorted(durations, key=durations.get)
    spans, statements = inert_spans(source), StatementIndex(source)
    equivalent = _equivalents(config, module)
    source_lines = source.splitlines()
    before = _spent(stem)
    zygote = mutation_fork.Zygote(tests, import_name(module), WORK / f"{stem}.zygote.log")
    patched = 0
    timing = {"patched": [0, 0.0], "fresh": [0, 0.0]}  # mutants run each way, their seconds
    killers: list[str] = []  # the tests that killed the latest mutants, the newest first
    killer_file = WORK / f"{stem}.killer"
    with contextlib.closing(zygote), use_db(str(db), WorkDB.Mode.open) as work_db:
        todo = list(work_db.pending_work_items)
        if args.survivors:
            todo += [item for item, result in work_db.completed_work_items
                     if result.test_outcome == TestOutcome.SURVIVED]
        timed_out: set[str] = set()  # re-tested under TIMEOUT_RETEST times their limit
        if args.timeouts:
            again = [item for item, result in work_db.completed_work_items
                     if result.test_outcome == TestOutcome.KILLED and result.output == "timeout"]
            timed_out = {item.job_id for item in again}
            todo += again
        if args.sample is not None and len(todo) > args.sample:
            # A seeded uniform sample: the rate of its mutants estimates the module's; a
            # later run (without --sample) tests the rest.
            todo = random.Random(args.seed).sample(todo, args.sample)
        todo.sort(key=lambda item: item.mutations[0].start_pos)
        print(f"{module}: {len(todo)} mutants to test, subset {len(durations)} tests "
              f"{sum(durations.values()):.1f} s + {overhead:.1f} s start", flush=True)
        ran = 0
        for n, item in enumerate(todo, 1):
            (spec,) = item.mutations
            pos = tuple(spec.start_pos)
            skip = inert_reason(spans, pos)
            if skip:
                work_db.set_result(item.job_id, WorkResult(
                    worker_outcome=WorkerOutcome.SKIPPED, output=f"equivalent: {skip}"))
                continue
            mutated = _mutant(source, spec)
            if mutated is None:
                work_db.set_result(item.job_id, WorkResult(worker_outcome=WorkerOutcome.NO_TEST))
                continue
            mutated_lines = mutated.splitlines()
            skip = _listed(equivalent, spec.operator_name, source_lines[pos[0] - 1],
                           mutated_lines[pos[0] - 1] if pos[0] <= len(mutated_lines) else "",
                           pos[0])
            if skip:
                work_db.set_result(item.job_id, WorkResult(
                    worker_outcome=WorkerOutcome.SKIPPED, output=f"equivalent: {skip}"))
                continue
            try:
                compile(mutated, str(target), "exec", dont_inherit=True)
            except SyntaxError as e:  # e.g. ``**mapping`` mutated to ``* *mapping``
                work_db.set_result(item.job_id, WorkResult(
                    worker_outcome=WorkerOutcome.NORMAL, test_outcome=TestOutcome.INCOMPETENT,
                    output=f"does not compile: {e.msg}"))
                continue
            diff = _diff(source, mutated, module)
            chosen = select(lines, statements.lines(pos))
            if chosen is not None and not chosen:
                work_db.set_result(item.job_id, WorkResult(
                    worker_outcome=WorkerOutcome.NORMAL, test_outcome=TestOutcome.SURVIVED,
                    output=UNCOVERED, diff=diff))
                continue
            order = by_speed if chosen is None else [t for t in by_speed if t in chosen]
            order = _killers_first(order, killers)
            limit = _limit(durations, order, overhead, args.timeout)
            if item.job_id in timed_out:
                limit *= TIMEOUT_RETEST
            patch = None if chosen is None else changed_functions(source, mutated, str(target))
            verdict = None
            if patch is not None:
                killer_file.unlink(missing_ok=True)
                verdict = zygote.run(mutated, patch, order, limit, killer_file)
                way = "patched"
                if verdict.code not in (None, 0) and killer_file.exists():
                    _promote(killers, killer_file.read_text())
            if verdict is None or verdict.code == mutation_fork.PATCH_FAILED:
                files = sorted({t.split("::")[0] for t in order})
                verdict = mutation_fork.run_mutant(files, None if chosen is None else order,
                                                   import_name(module), target, mutated, limit)
                way = "fresh"
            patched += way == "patched"
            timing[way][0] += 1
            timing[way][1] += verdict.seconds
            ran += 1
            if verdict.timed_out:
                outcome, output = TestOutcome.KILLED, "timeout"
            elif verdict.code in (0,):
                outcome, output = TestOutcome.SURVIVED, f"{len(order)} tests passed"
            elif verdict.code in INCOMPETENT_CODES:
                outcome, output = TestOutcome.INCOMPETENT, f"pytest exit {verdict.code}"
            else:
                outcome, output = TestOutcome.KILLED, f"pytest exit {verdict.code}"
            work_db.set_result(item.job_id, WorkResult(
                worker_outcome=WorkerOutcome.NORMAL, test_outcome=outcome, output=output,
                diff=diff))
            if n % 50 == 0 or n == len(todo):
                spent = time.perf_counter() - started
                print(f"  {n}/{len(todo)} ({ran} run, {patched} patched in) {spent:.0f} s",
                      flush=True)
                _save_spent(stem, before, time.perf_counter() - started, ran, timing)
                _export_results(module, db, source)
    _save_spent(stem, before, time.perf_counter() - started, ran, timing)
    _export_results(module, db, source)
    return tally_db(module, db, config)


def _killers_first(order: list[str], killers: list[str]) -> list[str]:
    """``order`` with the latest killers that it contains moved to the front."""
    first = [t for t in killers if t in order]
    return first + [t for t in order if t not in first] if first else order


def _promote(killers: list[str], test: str) -> None:
    if test in killers:
        killers.remove(test)
    killers.insert(0, test)
    del killers[KILLERS:]


def retest_with(module: str, files: list[str], config: dict, args) -> Tally:
    """Re-test the survivors of ``module``'s DB with only the test ``files`` (new tests, say):
    a mutant they kill is recorded killed; one they do not kill stays a survivor (the earlier
    verdict of the whole subset stands). Cheap: no baseline, each mutant a fresh pytest run
    of just these files."""
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import TestOutcome, WorkerOutcome, WorkResult

    stem = _stem(module)
    db = _init(module, stem, False)
    target = ROOT / module
    source = target.read_text()
    clean = mutation_fork.run_mutant(files, None, import_name(module), target, source, 600.0)
    if clean.code != 0:
        raise SystemExit(f"{module}: {' '.join(files)} fail on the unmutated code")
    limit = 30.0 + 3.0 * clean.seconds
    with use_db(str(db), WorkDB.Mode.open) as work_db:
        todo = [item for item, result in work_db.completed_work_items
                if result.test_outcome == TestOutcome.SURVIVED]
        print(f"{module}: {len(todo)} survivors to re-test with {len(files)} files "
              f"({clean.seconds:.1f} s a run)", flush=True)
        killed = 0
        for item in todo:
            (spec,) = item.mutations
            mutated = _mutant(source, spec)
            verdict = mutation_fork.run_mutant(files, None, import_name(module), target,
                                               mutated, limit)
            if verdict.code != 0 and verdict.code not in INCOMPETENT_CODES:  # failed / limit
                killed += 1
                work_db.set_result(item.job_id, WorkResult(
                    worker_outcome=WorkerOutcome.NORMAL, test_outcome=TestOutcome.KILLED,
                    output="timeout" if verdict.timed_out else f"pytest exit {verdict.code}",
                    diff=_diff(source, mutated, module)))
        print(f"  {killed} of {len(todo)} killed", flush=True)
    _export_results(module, db, source)
    return tally_db(module, db, config)


def _save_spent(stem: str, before: dict, seconds: float, ran: int, timing: dict) -> None:
    """The module's totals: the earlier runs' (``before``) plus this run's so far."""
    spent = {"seconds": before["seconds"] + seconds, "ran": before["ran"] + ran}
    for way, (count, secs) in timing.items():
        old_count, old_secs = before.get(way, [0, 0.0])
        spent[way] = [old_count + count, old_secs + secs]
    (WORK / f"{stem}.spent.json").write_text(json.dumps(spent))


def _stem(module: str) -> str:
    return module.replace("/", "_").removesuffix(".py")


def _spent(stem: str) -> dict:
    """Wall seconds and mutants run, summed over the runs that made the module's DB."""
    path = WORK / f"{stem}.spent.json"
    return json.loads(path.read_text()) if path.exists() else {"seconds": 0.0, "ran": 0}


def tally_db(module: str, db: Path, config: dict | None = None) -> Tally:
    """Count the module's DB (see :func:`tally_rows`)."""
    from cosmic_ray.work_db import WorkDB, use_db

    with use_db(str(db), WorkDB.Mode.open) as work_db:
        rows = [_result_row(item.mutations[0], result)
                for item, result in work_db.completed_work_items]
        total = work_db.num_work_items
    stamp = db.with_suffix(".sha256")
    stale = not stamp.exists() or stamp.read_text() != _digest(module)
    return tally_rows(module, rows, total, stale, _spent(_stem(module)), config)


def tally_rows(module: str, rows: list[dict], total: int, stale: bool, spent: dict,
               config: dict | None = None) -> Tally:
    """Count a module's results; a survivor that an ``[[equivalent]]`` entry (of ``config``)
    names — an entry added after it was run — counts as equivalent."""
    equivalent = _equivalents(config or {}, module)
    source_lines = (ROOT / module).read_text().splitlines()
    tally = Tally(module, seconds=spent["seconds"], ran=spent["ran"], stale=stale,
                  timing={w: spent[w] for w in ("patched", "fresh") if w in spent})
    for r in rows:
        output = r["output"] or ""
        if output.startswith(CARRIED):
            tally.carried += 1
            output = output[len(CARRIED):]
        if r["worker"] == "skipped":
            tally.equivalent += 1
        elif r["test"] == "killed":
            tally.killed += 1
            tally.timeouts += output == "timeout"
        elif r["test"] == "survived":
            diff = (r["diff"] or "").splitlines()
            changed = [d for d in diff if d.startswith("+") and not d.startswith("+++")]
            # the line as it was when the mutant ran (the file may have moved on since)
            was = [d[1:] for d in diff if d.startswith("-") and not d.startswith("---")]
            line_no = r["line"]
            source = was[0] if was else (
                source_lines[line_no - 1] if line_no <= len(source_lines) else "")
            if changed and _listed(equivalent, r["operator"], source, changed[0][1:], line_no):
                tally.equivalent += 1
                continue
            tally.survived.append((line_no, r["operator"], " ".join(changed)[:90],
                                   output == UNCOVERED))
        elif r["test"] == "incompetent":
            tally.incompetent += 1
    tally.untested = total - len(rows)
    tally.survived.sort()
    return tally


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score interval of a rate of ``k`` in ``n`` (95 % for z = 1.96)."""
    p, z2 = k / n, z * z
    mid, half = p + z2 / (2 * n), z * ((p * (1 - p) + z2 / (4 * n)) / n) ** 0.5
    return (mid - half) / (1 + z2 / n), (mid + half) / (1 + z2 / n)


def report(tallies: list[Tally]) -> str:
    rows = [f"{'module':<32}{'killed':>8}{'survived':>10}{'equiv.':>8}{'rate':>8}  target"
            f"{'run':>7}{'wall s':>8}  untested"]
    for t in tallies:
        if t.untested is None:
            rows.append(f"{t.module:<32}{'-':>8}{'-':>10}{'-':>8}{'-':>8}  NOT RUN")
            continue
        mark = "PASS" if t.rate >= TARGET else "SHORT"
        if t.untested:
            mark = "PART"  # some mutants not tested: the rate is of those tested
        stale = "  STALE: the module changed since this DB was made" if t.stale else ""
        if t.untested and t.scored:
            lo, hi = wilson(t.killed, t.scored)
            stale += f"  (95 % interval of the rate if those run are a sample: {lo:.1%}-{hi:.1%})"
        rows.append(f"{t.module:<32}{t.killed:>8}{len(t.survived):>10}{t.equivalent:>8}"
                    f"{t.rate:>8.1%}  {mark:<6}{t.ran:>7}{t.seconds:>8.0f}  {t.untested}{stale}")
    for t in tallies:
        ways = [f"{n} {way} {sec / n:.2f} s each" for way, (n, sec) in t.timing.items() if n]
        if ways:
            rows.append(f"timing {t.module}: " + ", ".join(ways)
                        + f"; {t.timeouts} killed by their time limit"
                        + (f"; {t.carried} results carried over from an earlier version of "
                           "the module (their function unchanged)" if t.carried else ""))
    for t in tallies:
        for line, op, diff, uncovered in t.survived:
            note = " [not executed by the subset]" if uncovered else ""
            rows.append(f"survivor {t.module}:{line} {op}: {diff}{note}")
    return "\n".join(rows) + "\n"


def _tally_stored(module: str, config: dict) -> Tally:
    """The module's results without running anything: its work DB, else its committed
    results file, else NOT RUN."""
    db = WORK / f"{_stem(module)}.sqlite"
    if db.exists():
        return tally_db(module, db, config)
    data = _load_results(_stem(module))
    if data is None:
        return Tally(module, untested=None)
    return tally_rows(module, data["results"], data["mutants"],
                      data["source_sha256"] != _digest(module), data["spent"], config)


def load_config() -> dict:
    """``mutation.toml`` with the ``[[equivalent]]`` entries of every file in
    ``mutation-equivalent/`` appended to its own."""
    config = tomllib.loads(CONFIG.read_text())
    for path in sorted(EQUIVALENTS.glob("*.toml")):
        config.setdefault("equivalent", []).extend(
            tomllib.loads(path.read_text()).get("equivalent", []))
    return config


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("modules", nargs="*", help="modules to mutate (default: all)")
    parser.add_argument("--timeout", type=float, default=120.0,
                        help="upper bound of a mutant's time limit, seconds")
    parser.add_argument("--fresh", action="store_true", help="discard earlier results")
    parser.add_argument("--survivors", action="store_true", help="re-test earlier survivors")
    parser.add_argument("--sample", type=int, metavar="N",
                        help="test only a seeded random sample of N of the pending mutants")
    parser.add_argument("--seed", type=int, default=0, help="the sample's seed")
    parser.add_argument("--retest-with", nargs="+", metavar="TESTFILE",
                        help="re-test the survivors with only these test files (new tests)")
    parser.add_argument("--timeouts", action="store_true",
                        help="re-test mutants killed by their time limit (under 3x that limit)")
    parser.add_argument("--report", type=Path, help="also write the report to this file")
    parser.add_argument("--tally", action="store_true",
                        help="run nothing: report the results already in the work DBs")
    args = parser.parse_args()
    config = load_config()
    modules = config["modules"]
    chosen = args.modules or list(modules)
    unknown = [m for m in chosen if m not in modules]
    if unknown:
        parser.error(f"not in {CONFIG.name}: {', '.join(unknown)}")
    os.chdir(ROOT)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # the child's group is ended too
    if args.tally:
        tallies = [_tally_stored(m, config) for m in chosen]
    else:
        mutation_fork.preload(PACKAGE)
        tallies = [retest_with(m, args.retest_with, config, args) if args.retest_with
                   else run_module(m, modules[m]["tests"], config, args) for m in chosen]
    text = report(tallies)
    print("\n" + text, end="")
    if args.report:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                              capture_output=True, text=True).stdout.strip()
        args.report.write_text(
            f"# make mutate report, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
            f"sources of commit {head}.\n# rate = killed / (killed + survived); 'run' = mutants "
            "run and 'wall s' = seconds, summed over the runs that filled each work DB; "
            "'untested' = mutants not run yet.\n" + text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
