"""The pytest plugin's defaults and refusals, in a temporary project run with pytester:
services on free ports without protocol listeners unless asked, a controller id naming its
test cut to 48 characters, and an external server whose ``/health`` is not 200 stopping the
session saying so (API.md ``GET /health``)."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import pytest


@pytest.fixture
def unhealthy() -> Iterator[str]:
    """A server answering 503 to every GET."""

    class Handler(BaseHTTPRequestHandler):
        def do_GET(self) -> None:  # noqa: N802 (the stdlib's name)
            self.send_response(503)
            self.send_header("Content-Length", "0")
            self.end_headers()

        def log_message(self, *args: object) -> None:
            pass

    server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


def test_an_external_server_whose_health_is_not_200_stops_the_session(pytester, unhealthy):
    pytester.makepyfile("def test_x(motionsim_pmac):\n    pass\n")
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider",
                                          f"--motionsim-url={unhealthy}")
    assert result.ret == 3
    said = result.stdout.str() + result.stderr.str()
    assert f"--motionsim-url {unhealthy}: GET /health answered 503, not 200" in said


def test_services_take_free_ports_and_open_no_protocol_listeners(pytester):
    pytester.makepyfile("""
        from urllib.parse import urlsplit

        def test_ports(motionsim_server, motionsim_services):
            other = motionsim_services()
            ports = [urlsplit(s.url).port for s in (motionsim_server, other)]
            assert ports[0] != ports[1] and min(ports) >= 1024   # ephemeral, not fixed
            assert dict(motionsim_server.ports) == {} and dict(other.ports) == {}
    """)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=1)


def test_a_controller_id_names_its_test_cut_to_48_characters(pytester):
    name = "test_" + "a_very_long_test_name_" * 4
    pytester.makepyfile(f"""
        def {name}(motionsim_pmac):
            stem, tag = motionsim_pmac.id.rsplit("-", 1)
            assert stem == "{name}"[:48] and len(tag) == 6
    """)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=1)


def test_a_host_still_waiting_when_its_test_ends_is_released_not_cut_off(pytester):
    """The ``motionsim`` fixture's teardown releases every holder of a host-paced clock
    (API.md ``DELETE /controllers/{id}/clock/holders/{name}``), so a host thread still
    waiting in ``run-until`` gets ``released`` and stops, instead of dying on the service's
    closed connection. (The streamer is released first, while ``main`` still keeps time
    still: its wait ends ``released``, not at its simulated deadline.)"""
    pytester.makepyfile("""
        HOSTS = []

        def test_leaves_a_host_waiting(motionsim):
            motionsim.host_paced("pmac")
            host = motionsim.host("pmac", "streamer")
            motionsim.hold("pmac", "main")  # main acts from here on: time stands still
            HOSTS.append((host, host.start(lambda h: h.wait_for("breq", 60.0, cs=1))))
            assert [h["name"] for h in motionsim.clock("pmac").holders] == ["streamer", "main"]

        def test_its_wait_ended_released():
            host, future = HOSTS[0]
            assert future.result(timeout=60) is None
            assert host.outcome == "released" and host.released
    """)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=2)


def test_a_host_waiting_on_a_per_test_controller_is_released_when_it_is_deleted(pytester):
    """``motionsim_pmac`` (a controller per test on the session's service): its teardown
    releases the controller's holders before deleting it, so a host still waiting in
    ``run-until`` ends ``released`` (API.md ``DELETE .../clock/holders/{name}``)."""
    pytester.makepyfile("""
        HOSTS = []

        def test_leaves_a_host_waiting(motionsim_pmac):
            motionsim_pmac.host_paced()
            host = motionsim_pmac.host("streamer")
            motionsim_pmac.hold("main")  # main acts from here on: time stands still
            HOSTS.append((host, host.start(lambda h: h.wait_for("breq", 60.0, cs=1))))

        def test_its_wait_ended_released():
            host, future = HOSTS[0]
            assert future.result(timeout=60) is None
            assert host.outcome == "released"
    """)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=2)


def test_an_external_server_that_cannot_be_reached_stops_the_session_with_code_3(pytester):
    import socket

    with socket.socket() as s:  # a port nothing listens on once closed
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    pytester.makepyfile("def test_x(motionsim_pmac):\n    pass\n")
    url = f"http://127.0.0.1:{port}"
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider", f"--motionsim-url={url}")
    assert result.ret == 3
    assert f"--motionsim-url {url}: cannot reach it" in result.stdout.str() + result.stderr.str()


def test_the_session_service_is_not_external(pytester):
    """``motionsim_server.external``: False for the service the plugin serves itself."""
    pytester.makepyfile("def test_x(motionsim_server):\n"
                        "    assert motionsim_server.external is False\n")
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=1)
