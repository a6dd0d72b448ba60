"""The service's event loop (setting ``event_loop``, app/http_server.py): uvloop when
installed unless asyncio is asked for, and the loop ``motionsim serve`` really runs on."""

import asyncio
import os
import subprocess
import sys

import pytest
import uvloop
from motionsim.app.http_server import loop_factory, run_service
from motionsim.app.settings import Settings, build_settings


async def _loop_type() -> type:
    return type(asyncio.get_running_loop())


def test_auto_and_uvloop_run_the_service_on_uvloop_and_asyncio_on_the_standard_loop():
    assert loop_factory("asyncio") is None
    assert run_service(_loop_type(), Settings(event_loop="auto").event_loop) is uvloop.Loop
    assert run_service(_loop_type(), "uvloop") is uvloop.Loop
    standard = run_service(_loop_type(), "asyncio")
    assert standard is not uvloop.Loop and issubclass(standard, asyncio.BaseEventLoop)


def test_the_setting_is_read_from_the_environment_and_checked():
    os.environ["MOTIONSIM_EVENT_LOOP"] = "asyncio"
    try:
        assert build_settings(None).event_loop == "asyncio"
    finally:
        del os.environ["MOTIONSIM_EVENT_LOOP"]
    with pytest.raises(ValueError, match="event_loop"):
        Settings(event_loop="trio")


def test_uvloop_asked_for_and_missing_is_an_import_error():
    # a child interpreter where importing uvloop fails, as on a machine without it
    code = ("import sys; sys.modules['uvloop'] = None\n"
            "from motionsim.app.http_server import loop_factory\n"
            "assert loop_factory('auto') is None\n"
            "try:\n    loop_factory('uvloop')\nexcept ImportError:\n    print('refused')\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60, check=True).stdout
    assert out.strip() == "refused"
