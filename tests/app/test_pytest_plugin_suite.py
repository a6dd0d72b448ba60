"""The pytest plugin in a user's suite: run in a temporary project with pytester, as a host
author's own tests would run it (the plugin comes from the installed entry point).

- ``examples/pytest`` (what the README points to) passes as written, against the
  session-scoped service and against an external server named by ``--motionsim-url`` or
  ``MOTIONSIM_URL``; the controllers each test made are deleted afterwards;
- one service serves the whole session, a fresh controller each test;
- a starving host fails ``assert_fed`` with the instant, line, lines ahead and diagnosed
  cause, and the failed test's report carries the event log's tail and the path of the whole.
"""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest
from motionsim.app.client import MotionSimClient
from motionsim.app.embedded import EmbeddedService
from motionsim.app.settings import Settings

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "pytest"
EXAMPLE_TESTS = 5


@pytest.fixture(scope="module", autouse=True)
def _serve_and_subscribe_once_here():
    """pytester's in-process runs drop from ``sys.modules`` what they imported first; uvicorn
    imports its WebSocket protocol lazily, on the first server start, so a later test of this
    process would get a second copy of those modules and its WebSocket upgrades would fail.
    One served socket here, before any inner run, imports them in this process for good."""
    from websockets.sync.client import connect

    with EmbeddedService(Settings(port=0, clock={"mode": "virtual"}, pmac_port=0, trio_port=0,
                                  controllers=[{"id": "w", "kind": "pmac"}])) as served:
        url = served.url.replace("http", "ws") + "/controllers/w/events"
        with connect(url, compression=None, proxy=None, open_timeout=10) as ws:
            ws.recv(timeout=10)
    yield


def _copy_examples(pytester: pytest.Pytester) -> None:
    for path in EXAMPLES.glob("test_*.py"):
        shutil.copy(path, pytester.path / path.name)


@pytest.fixture
def external():
    """A server already running, as ``make run`` or docker compose would leave one."""
    with EmbeddedService(Settings(port=0, clock={"mode": "virtual"}, pmac_port=0,
                                  trio_port=0)) as served:
        yield served


def test_the_pytest_examples_pass_on_the_session_service(pytester):
    _copy_examples(pytester)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=EXAMPLE_TESTS)


def test_the_same_examples_run_against_an_external_server_named_by_the_option(
        pytester, external):
    _copy_examples(pytester)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider",
                                          f"--motionsim-url={external.url}")
    result.assert_outcomes(passed=EXAMPLE_TESTS)
    with MotionSimClient(external.url) as client:
        # the defaults pmac and trio are the server's; every test's own controller is gone
        assert sorted(c["id"] for c in client.controllers()) == ["pmac", "trio"]


def test_the_environment_variable_names_the_external_server_too(pytester, external,
                                                                monkeypatch):
    monkeypatch.setenv("MOTIONSIM_URL", external.url)
    pytester.makepyfile(f"""
        def test_on_the_external_server(motionsim_server, motionsim_pmac):
            assert motionsim_server.external
            assert motionsim_pmac.url == motionsim_server.url == {external.url!r}
    """)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=1)


@pytest.fixture
def guarded():
    """A server already running with ``--token``."""
    with EmbeddedService(Settings(port=0, clock={"mode": "virtual"}, pmac_port=0,
                                  trio_port=0, token="s3cret")) as served:
        yield served


def test_a_token_server_runs_the_suite_with_the_token_option(pytester, guarded):
    pytester.makepyfile("""
        def test_on_the_guarded_server(motionsim_pmac):
            motionsim_pmac.set_variable("P1", 3)
            assert motionsim_pmac.get_variable("P1") == 3
            motionsim_pmac.terminal("OPEN PLC 1 CLEAR P2=P2+1 CLOSE")
            with motionsim_pmac.subscribe(types=["plc"], timeout=10) as events:
                motionsim_pmac.terminal("ENABLE PLC 1")
                assert next(iter(events))["state"] == "enabled"
    """)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider",
                                          f"--motionsim-url={guarded.url}",
                                          "--motionsim-token=s3cret")
    result.assert_outcomes(passed=1)


def test_a_token_server_without_the_token_stops_the_session_saying_so(pytester, guarded):
    pytester.makepyfile("def test_x(motionsim_pmac):\n    pass\n")
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider",
                                          f"--motionsim-url={guarded.url}")
    assert result.ret != 0
    assert "--motionsim-token" in result.stdout.str() + result.stderr.str()


def test_the_motionsim_fixture_serving_a_token_gives_its_client_the_token(pytester):
    pytester.makeconftest("""
        import pytest
        from motionsim.app.settings import Settings

        @pytest.fixture
        def motionsim_settings():
            return Settings(port=0, clock={"mode": "virtual"}, token="t0k")
    """)
    pytester.makepyfile("""
        import httpx

        def test_guarded(motionsim):
            assert httpx.get(motionsim.url + "/controllers").status_code == 401
            motionsim.set_variable("pmac", "P1", 4)
            assert motionsim.get_variable("pmac", "P1") == 4
    """)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=1)


def test_an_external_server_that_is_not_there_stops_the_session_with_its_url(pytester):
    pytester.makepyfile("def test_x(motionsim_pmac):\n    pass\n")
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider",
                                          "--motionsim-url=http://127.0.0.1:9")
    assert result.ret != 0
    said = result.stdout.str() + result.stderr.str()
    # issue 36 item 4: a closed port is "cannot reach", not "GET /health is not ok"
    assert "--motionsim-url http://127.0.0.1:9: cannot reach it" in said
    assert "not ok" not in said


def test_one_service_per_session_and_a_fresh_controller_per_test(pytester):
    pytester.makepyfile("""
        seen = []

        def test_a(motionsim_server, motionsim_pmac):
            motionsim_pmac.set_variable("P1", 7)
            motionsim_pmac.advance(0.25)
            seen.append((motionsim_server.url, motionsim_pmac.id))

        def test_b(motionsim_server, motionsim_pmac):
            assert motionsim_pmac.get_variable("P1") == 0
            assert motionsim_pmac.clock().t == 0.0
            seen.append((motionsim_server.url, motionsim_pmac.id))

        def test_c(motionsim_server):
            (url_a, id_a), (url_b, id_b) = seen
            assert url_a == url_b == motionsim_server.url
            assert id_a != id_b and id_a.startswith("test_a-") and id_b.startswith("test_b-")
            with motionsim_server.client() as client:
                assert client.controllers() == []   # both deleted after their test
    """)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=3)


SLOW_HOST = """
    from motionsim.app.pytest_plugin import assert_fed

    def test_slow_host(motionsim_controllers):
        pmac = motionsim_controllers("pmac", id="slow", config={"i16": 5, "i17": 10})
        pmac.define_rotary(1, 600)
        sent = 0
        while sent < 40:
            have = pmac.coord(1)["rotary"]["lines_ahead"]
            batch = [f"TM100 TA10 TS0 X{n % 2 * 10}" for n in range(sent, sent + 10 - have)]
            pmac.load_lines(1, batch)
            sent += len(batch)
            if pmac.coord(1)["program"]["state"] == "idle":
                pmac.run(1)
            pmac.run_until("breq", 5.0, cs=1, level=True)
            pmac.advance(REACTION_S)
        assert_fed(pmac, cs=1, total_lines={1: 40})
"""


def test_tsrm_i16_a_host_slower_than_its_i16_lines_fails_assert_fed_with_the_diagnosis(
        pytester):
    """BREQ rises when lines ahead fall below I16 (TSRM I16); the host must refill within the
    time the lines then ahead take to execute. One that reacts 0.8 s after BREQ lets the
    program run dry: the message names the instant, the line the program ran dry after, the
    lines ahead, the cause, and the arithmetic (time covered < the host's answer)."""
    pytester.makepyfile(SLOW_HOST.replace("REACTION_S", "0.8"))
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(failed=1)
    out = result.stdout.str()
    # each message may stand twice (the traceback and, on a wide terminal, the summary line)
    pattern = (r"  &1: buffer_empty at t=([\d.]+) s for [\d.]+ ms, after line "
               r"(\d+) with 0 lines ahead \(40 loaded in all\) — cause "
               r"host_latency: lines ahead fell below I16=5 at ([\d.]+) s; they "
               r"covered ([\d.]+) ms of motion but the host answered after "
               r"([\d.]+) ms")
    episodes = sorted(set(re.findall(pattern, out)))
    assert len(episodes) == 3, out                  # one per refill of 10 lines, before line 40
    assert [int(e[1]) for e in episodes] == [10, 20, 30]
    for t, _, t16, covered, answered in episodes:
        assert float(t) - float(t16) == pytest.approx(float(covered) / 1e3, abs=2e-6)
        assert float(covered) < float(answered) == 800.0
    assert "slow starved 3 time(s)" in out
    # issue 36 item 5: the id once in the header, not on every line; no source of assert_fed
    assert "slow &1:" not in out
    assert "__tracebackhide__" not in out and "def assert_fed" not in out


def test_a_host_that_keeps_up_passes_assert_fed(pytester):
    pytester.makepyfile(SLOW_HOST.replace("REACTION_S", "0.002"))
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=1)


def test_a_failed_test_reports_the_event_log_tail_and_the_path_of_the_whole(pytester):
    pytester.makepyfile(SLOW_HOST.replace("REACTION_S", "0.8"))
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider", "-rA")
    out = result.stdout.str()
    header = re.search(r"motionsim events: slow \(last (\d+) of (\d+)\)", out)
    assert header, out
    assert int(header[1]) == 40 < int(header[2])
    whole = Path(re.search(r"whole log: (\S+)", out)[1])
    logged = [json.loads(line) for line in whole.read_text().splitlines()]
    assert len(logged) == int(header[2])
    assert [e["seq"] for e in logged] == list(range(1, len(logged) + 1))
    assert json.dumps(logged[-1]) in out        # the tail is the log's end


def test_the_function_scoped_fixture_attaches_its_controllers_logs_too(pytester):
    pytester.makepyfile("""
        def test_fails(motionsim):
            motionsim.advance("pmac", 0.01)
            assert False, "the host did something wrong"
    """)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(failed=1)
    out = result.stdout.str()
    assert "motionsim events: pmac" in out and "motionsim events: trio" in out
