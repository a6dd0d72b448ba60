"""Request bodies refused before any route: size, media type, UTF-8, depth, finite numbers.

Each refusal has the documented error body and changes nothing (the event log is compared).
"""

from __future__ import annotations

import pytest

from tests.conftest import rest_client

pytestmark = pytest.mark.anyio

JSON = {"content-type": "application/json"}


async def _next(api) -> int:
    return (await api.get("/controllers/d/events")).json()["next"]


async def _unchanged(api, method, url, *, before=None, **kw):
    """Send the request; assert the clock and the log did not move; return the response."""
    t0 = (await api.get("/controllers/d/clock")).json()["t"]
    n0 = await _next(api) if before is None else before
    r = await api.request(method, url, **kw)
    assert (await api.get("/controllers/d/clock")).json()["t"] == t0
    assert await _next(api) == n0
    return r


async def test_a_body_over_the_limit_is_413_with_the_error_body(make_app):
    async with rest_client(make_app(max_body_bytes=1024)) as api:
        r = await _unchanged(api, "POST", "/controllers/d/terminal",
                             content=b'{"command": "' + b"x" * 2000 + b'"}', headers=JSON)
        assert r.status_code == 413
        assert r.json()["code"] == "body_too_large" and r.json()["limit"] == 1024
        assert "max_body_bytes" in r.json()["message"]
        ok = await api.post("/controllers/d/terminal", json={"command": "NOW small"})
        assert ok.status_code == 200


async def test_invalid_utf8_is_422_naming_the_byte(api):
    r = await _unchanged(api, "POST", "/controllers/d/clock/advance",
                         content=b'{"seconds": "\xff"}', headers=JSON)
    assert r.status_code == 422
    assert (r.json()["code"], r.json()["field"], r.json()["position"]) == (
        "validation_error", "body", 13)
    assert "not valid UTF-8 (byte 13)" in r.json()["message"]


async def test_over_deep_json_is_422_not_500(api):
    for depth in (40, 100_000):
        body = b'{"seconds": ' + b"[" * depth + b"]" * depth + b"}"
        r = await _unchanged(api, "POST", "/controllers/d/clock/advance", content=body,
                             headers=JSON)
        assert r.status_code == 422, depth
        assert r.json()["message"] == "JSON nested deeper than 32 levels"


@pytest.mark.parametrize("literal", [b"NaN", b"Infinity", b"-Infinity", b"1e999"])
async def test_nan_or_infinity_anywhere_in_a_body_is_422(api, literal):
    r = await _unchanged(api, "POST", "/controllers/d/clock/advance",
                         content=b'{"seconds": ' + literal + b"}", headers=JSON)
    assert (r.status_code, r.json()["code"], r.json()["field"]) == (
        422, "validation_error", "seconds")
    assert "is not a finite number" in r.json()["message"]
    nested = b'{"event": {"type": "tick", "n": [1, ' + literal + b']}, "timeout_s": 1}'
    r = await _unchanged(api, "POST", "/controllers/d/clock/run-until", content=nested,
                         headers=JSON)
    assert (r.status_code, r.json()["field"]) == (422, "event.n.1")


async def test_an_integer_too_long_to_convert_is_422_not_500(api):
    r = await _unchanged(api, "POST", "/controllers/d/clock/advance",
                         content=b'{"seconds": ' + b"9" * 5000 + b"}", headers=JSON)
    assert (r.status_code, r.json()["code"]) == (422, "validation_error")


async def test_a_post_without_json_content_type_gets_a_message_saying_so(api):
    r = await _unchanged(api, "POST", "/controllers/d/clock/advance", content=b"seconds=1",
                         headers={"content-type": "application/x-www-form-urlencoded"})
    assert (r.status_code, r.json()["code"]) == (415, "unsupported_media_type")
    assert "Content-Type: application/json" in r.json()["message"]
    assert "application/x-www-form-urlencoded" in r.json()["message"]
    r = await _unchanged(api, "POST", "/controllers/d/clock/advance",
                         content=b'{"seconds": 1}')
    assert r.status_code == 415 and "no Content-Type" in r.json()["message"]
    r = await _unchanged(api, "POST", "/controllers/d/terminal", content=b'{"command": "NOW a"}',
                         headers={"content-type": "text/plain"})
    assert r.status_code == 415


async def test_a_post_without_a_body_needs_no_content_type(api):
    r = await api.post("/controllers/d/reset")
    assert r.status_code in (200, 204), r.text


async def test_charset_and_json_suffix_media_types_are_json(api):
    for media in ("application/json; charset=utf-8", "application/merge-patch+json"):
        r = await api.post("/controllers/d/clock/advance", content=b'{"seconds": 0.01}',
                           headers={"content-type": media})
        assert r.status_code == 200, (media, r.text)
