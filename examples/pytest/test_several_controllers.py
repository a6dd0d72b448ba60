"""Several controllers, kinds and services in one test: the factory fixtures.

``motionsim_controllers(kind, config=..., clock=..., server=...)`` makes as many controllers
as the test needs on the session's service (or on ``server``); ``motionsim_services()``
starts another service of its own settings (e.g. a PMAC on its Ethernet port). Everything is
deleted / stopped after the test.
"""

from __future__ import annotations

import socket

from motionsim.app.settings import Settings


def test_two_pmacs_and_a_trio_side_by_side(motionsim_controllers):
    fast = motionsim_controllers("pmac", config={"i16": 5, "i17": 10})
    slow = motionsim_controllers("pmac", config={"i16": 2, "i17": 4})
    trio = motionsim_controllers("trio")
    assert len({fast.id, slow.id, trio.id}) == 3
    assert (fast.get_variable("I17"), slow.get_variable("I17")) == (10, 4)
    fast.advance(0.1)
    assert (fast.clock().t, slow.clock().t) == (0.1, 0.0)   # each has its own clock


def test_a_service_of_its_own_with_the_pmac_ethernet_port(motionsim_services,
                                                          motionsim_controllers):
    served = motionsim_services(Settings(clock={"mode": "virtual"}, pmac_port="auto",
                                         trio_port=0, controllers=[{"id": "pmac",
                                                                    "kind": "pmac"}]))
    socket.create_connection(("127.0.0.1", served.ports["pmac"]), timeout=5).close()
    trio = motionsim_controllers("trio", server=served)    # another controller beside it
    assert trio.url == served.url
