"""The dashboard in a real browser against a served motionsim: what the page *shows*.

The PMAC half streams a rotary program over REST the way a BREQ-driven host does; the Trio
half runs TN20-16's program. The tests run in file order on one page and one service (module
fixtures), each waiting until the page has applied every event the service logged (its
stream status carries the last seq) before reading the page.
"""

from __future__ import annotations

import re

import pytest

from tests.browser.page import caught_up, select, server_last_seq, shown, status
from tests.browser.scenario import run_tn20, stream_rotary

pytestmark = pytest.mark.timeout(240)

PMAC, TRIO = "p", "t"


def type_command(b, cid: str, command: str) -> None:
    box = b.page.locator(f'[data-controller="{cid}"] [data-role=command]')
    box.fill(command)
    box.press("Enter")


def wait_reply(b, cid: str, command: str, count: int) -> str:
    """The reply shown for the ``count``-th time ``command`` was typed (pending filled in)."""
    b.page.wait_for_function(
        """([cid, cmd, count]) => {
             const all = [...document.querySelectorAll(
               `[data-controller="${cid}"] [data-role=transcript] .entry`)]
               .filter((e) => e.dataset.command === cmd);
             return all.length >= count && !all[count - 1].querySelector('.pending')
                    && all[count - 1].querySelector('.reply, .error'); }""",
        arg=[cid, command, count])
    entries = b.page.locator(f'[data-controller="{cid}"] [data-role=transcript] .entry')
    matching = [entries.nth(i) for i in range(entries.count())
                if entries.nth(i).get_attribute("data-command") == command]
    return matching[count - 1].locator(".reply, .error").first.inner_text()


def path_levels(d: str) -> set[float]:
    """The y values a step path's vertical segments reach."""
    return {float(v) for v in re.findall(r"V(-?[\d.]+)", d)}


# -- PMAC ---------------------------------------------------------------------------------


def test_rotary_stream_draws_lines_ahead_against_i16_i17_with_breq_beneath(browser, ms):
    b = browser
    stream_rotary(ms, PMAC, until_s=0.5)
    b.page.wait_for_selector(f'[data-tab="{PMAC}"]')
    select(b, PMAC)
    caught_up(b, ms, PMAC)
    chart = f'[data-controller="{PMAC}"] #cs-1 svg[data-role=rotary-chart]'
    b.page.wait_for_selector(f"{chart} line.level.i17", state="attached")
    i16 = b.page.locator(f"{chart} line.level.i16")
    i17 = b.page.locator(f"{chart} line.level.i17")
    assert (i16.get_attribute("data-level"), i17.get_attribute("data-level")) == ("5", "10")
    # on screen I17 is above I16 (y grows downwards)
    assert float(i17.get_attribute("y1")) < float(i16.get_attribute("y1"))
    breq = b.page.get_attribute(f"{chart} path[data-role=breq-trace]", "d")
    edges = ms.events(PMAC, types=["breq"]).events
    assert {e["level"] for e in edges} == {True, False}
    assert len(path_levels(breq)) == 2, breq        # it goes both high and low
    ahead = b.page.get_attribute(f"{chart} path[data-role=lines-ahead-trace]", "d")
    assert len(path_levels(ahead)) >= 5              # lines ahead rises to I17 and drains
    assert shown(b, PMAC, "#cs-1 [data-role=i16]") == "5"
    assert shown(b, PMAC, "#cs-1 [data-role=i17]") == "10"


def test_lines_ahead_shown_equals_pr_at_paused_instants(browser, ms):
    b = browser
    for step in range(6):
        ms.advance(PMAC, 0.0137 * (step + 1))
        ms.set_clock(PMAC, paused=True)
        caught_up(b, ms, PMAC)
        pr = ms.coord(PMAC, 1)["rotary"]["lines_ahead"]
        assert shown(b, PMAC, "#cs-1 [data-role=lines-ahead]") == str(pr)
        ms.set_clock(PMAC, paused=False)
        # and typed at the page's own terminal: PR's reply against what the page shows then
        type_command(b, PMAC, "PR")
        reply = wait_reply(b, PMAC, "PR", step + 1)
        caught_up(b, ms, PMAC)
        assert shown(b, PMAC, "#cs-1 [data-role=lines-ahead]") == reply.strip()


def test_a_pending_pr_is_filled_in_when_its_reply_arrives(browser, ms):
    b = browser
    entries = b.page.locator(f'[data-controller="{PMAC}"] .entry[data-command="PR"]')
    count = entries.count() + 1
    ms.set_clock(PMAC, paused=True)   # a paused PMAC runs no background cycle: no reply yet
    type_command(b, PMAC, "PR")
    b.page.wait_for_function("([sel, n]) => document.querySelectorAll(sel).length >= n",
                             arg=[f'[data-controller="{PMAC}"] .entry[data-command="PR"]', count])
    b.page.wait_for_function(  # the POST itself answered "pending": true
        "sel => !!document.querySelector(sel)",
        arg=f'[data-controller="{PMAC}"] .entry[data-command="PR"]:last-child .pending')
    ms.set_clock(PMAC, paused=False)
    ms.advance(PMAC, 0.01)
    reply = wait_reply(b, PMAC, "PR", count)
    assert reply.strip().isdigit()


def test_executing_line_is_highlighted_and_program_state_shown(browser, ms):
    b = browser
    caught_up(b, ms, PMAC)
    coord = ms.coord(PMAC, 1)
    assert shown(b, PMAC, "#cs-1 [data-role=program-state]") == coord["program"]["state"]
    starts = ms.events(PMAC, types=["move_start", "move_end"]).events
    executing = starts[-1]["n"] if starts[-1]["type"] == "move_start" else None
    rows = b.page.locator(f'[data-controller="{PMAC}"] #cs-1 tr.executing')
    if executing is None:
        assert rows.count() == 0
    else:
        assert rows.count() == 1 and rows.get_attribute("data-n") == str(executing)
        assert shown(b, PMAC, "#cs-1 [data-role=executing]") == f"line {executing}"


def test_running_out_of_lines_is_shaded_as_starvation(browser, ms):
    b = browser
    # the stream above stopped feeding at 60 lines: let the program drain
    ms.advance(PMAC, 1.5)
    caught_up(b, ms, PMAC)
    assert ms.coord(PMAC, 1)["program"]["state"] == "waiting"
    assert shown(b, PMAC, "#cs-1 [data-role=program-state]") == "waiting"
    assert b.page.locator(f'[data-controller="{PMAC}"] #cs-1 svg rect.starved').count() >= 1
    assert b.page.locator(f'[data-controller="{PMAC}"] #cs-1 svg line.sync-m').count() >= 1


def test_server_side_close_is_resumed_by_seq_without_gaps(browser, ms):
    b = browser
    before = caught_up(b, ms, PMAC)
    sockets = b.live_sockets(PMAC)
    assert sockets
    opened = len(b.sockets)
    for ws, server in sockets:   # the service ends the connection: 1012 "service restart"
        server.close(code=1012, reason="service restart")
        ws.close(code=1012, reason="service restart")
    for _ in range(5):    # events logged while the page may be disconnected
        ms.load_lines(PMAC, 1, ["TM20 X1"])
        ms.advance(PMAC, 0.05)
    b.page.wait_for_function(
        """([cid, n]) => {
             const el = document.querySelector(`[data-controller="${cid}"] [data-role=stream]`);
             return Number(el.dataset.reconnects) > n && el.dataset.state === "live"; }""",
        arg=[PMAC, int(before["reconnects"])])
    after = caught_up(b, ms, PMAC)
    seq = server_last_seq(ms, PMAC)
    assert int(after["lastSeq"]) == seq
    assert (after["gaps"], after["duplicates"]) == ("0", "0")
    assert int(after["received"]) == seq    # every event from seq 1 applied exactly once
    resumed = [url for url, _, _ in b.sockets[opened:] if f"/controllers/{PMAC}/events" in url]
    assert f"since={before['lastSeq']}" in resumed[0]   # resumed from the last seq it applied
    ms.set_clock(PMAC, paused=True)
    caught_up(b, ms, PMAC)
    pr = ms.coord(PMAC, 1)["rotary"]["lines_ahead"]
    assert shown(b, PMAC, "#cs-1 [data-role=lines-ahead]") == str(pr)
    ms.set_clock(PMAC, paused=False)


# -- Trio ---------------------------------------------------------------------------------


def stall_intervals(b, cid: str, axis: int) -> list[tuple[float, float | None]]:
    rects = b.page.locator(f'[data-controller="{cid}"] svg[data-role=axis-lanes] '
                           f'g[data-axis="{axis}"] rect.stall-bg')
    return [(float(r.get_attribute("data-t0")),
             float(r.get_attribute("data-t1")) if r.get_attribute("data-t1") else None)
            for r in rects.all()]


def idle_spans(ms, cid: str, axis: int) -> list[tuple[float, float | None]]:
    """From the service's log: when ``axis`` had MTYPE = NTYPE = 0 after its first move."""
    spans, start, moved = [], None, False
    for e in ms.events(cid, types=["axis"], limit=100_000).events:
        if e["axis"] != axis:
            continue
        idle = e["mtype"] == 0 and e["ntype"] == 0
        if idle and moved and start is None:
            start = e["t"]
        elif not idle:
            moved = True
            if start is not None:
                spans.append((start, e["t"]))
                start = None
    return spans + ([(start, None)] if start is not None else [])


def test_tn20_stall_axis_0_idle_while_its_process_waits_behind_axis_1(browser, ms):
    b = browser
    run_tn20(ms, TRIO, seconds=0.1)     # axis 0 runs dry behind axis 1's long move
    b.page.wait_for_selector(f'[data-tab="{TRIO}"]')
    select(b, TRIO)
    caught_up(b, ms, TRIO)
    stall = b.page.locator(f'[data-controller="{TRIO}"] .stall[data-axis="0"]')
    assert stall.get_attribute("data-process") == "1"
    assert "process buffer holds MOVE for axis 1" in stall.inner_text()
    row = b.page.locator(f'[data-controller="{TRIO}"] table.procs tr[data-process="1"]')
    assert row.locator("[data-role=state]").inner_text() == "blocked"
    assert "AXIS(0)" in row.inner_text()
    ((idle_from, idle_to),) = idle_spans(ms, TRIO, 0)
    assert idle_to is None                               # still idle at 0.1 s
    assert stall_intervals(b, TRIO, 0)[-1] == (pytest.approx(idle_from), None)
    # axis 1 only ever waits a servo period or two, at the start, behind axis 0's first move
    assert all(t1 is not None and t1 - t0 < 0.003 for t0, t1 in stall_intervals(b, TRIO, 1))
    lanes = f'[data-controller="{TRIO}"] svg[data-role=axis-lanes]'
    names = b.page.locator(f'{lanes} g[data-axis="1"] text.lane-text').all_text_contents()
    assert "MOVE" in names                             # move types by name, not code
    ms.advance(TRIO, 0.2)    # axis 0 moves again: the stall is history, closed where it ended
    caught_up(b, ms, TRIO)
    (first, *_rest) = idle_spans(ms, TRIO, 0)
    assert first[0] == pytest.approx(idle_from) and first[1] is not None
    assert first[1] - first[0] > 0.1                    # the long move's duration, not a blip
    # the stall ends when the process loads axis 0's move (its process buffer takes it), the
    # axis starts it at the next servo interrupt: within one servo period (1 ms) of each other
    period = 0.001
    assert any(t0 == pytest.approx(first[0]) and t1 is not None
               and first[1] - period - 1e-9 <= t1 <= first[1]
               for t0, t1 in stall_intervals(b, TRIO, 0))


def test_terminal_command_reply_in_transcript_with_history(browser, ms):
    b = browser
    command = "PRINT MTYPE AXIS(1)"
    type_command(b, TRIO, command)
    reply = wait_reply(b, TRIO, command, 1)
    assert reply.strip() == ms.terminal(TRIO, command).reply.strip()
    box = b.page.locator(f'[data-controller="{TRIO}"] [data-role=command]')
    box.press("ArrowUp")
    assert box.input_value() == command


# -- controllers and clocks ---------------------------------------------------------------


def test_controllers_created_and_deleted_live(browser, ms):
    b = browser
    form = b.page.locator("#create")
    form.locator("[name=cid]").fill("live1")
    form.locator("[name=kind]").select_option("trio")
    form.locator("[name=mode]").select_option("realtime")
    form.locator("button[type=submit]").click()
    b.page.wait_for_selector('[data-tab="live1"].on')
    assert "live1" in {c["id"] for c in ms.controllers()}
    ms.create_controller("pmac", id="live2", clock="virtual")     # by another client
    b.page.wait_for_selector('[data-tab="live2"]')
    b.page.click('[data-delete="live1"]')
    b.page.wait_for_selector('[data-tab="live1"]', state="detached")
    ms.delete_controller("live2")
    b.page.wait_for_selector('[data-tab="live2"]', state="detached")
    assert not {"live1", "live2"} & {c["id"] for c in ms.controllers()}


def test_clock_controls_disabled_where_they_cannot_act(browser, ms):
    b = browser
    ms.create_controller("pmac", id="rt", clock="realtime")
    b.page.wait_for_selector('[data-tab="rt"]')
    select(b, "rt")
    panel = '[data-controller="rt"] .clock'
    b.page.wait_for_selector(f'{panel} [data-role=clock-mode]:has-text("realtime")')
    assert b.page.is_disabled(f"{panel} [data-role=advance]")
    assert b.page.is_enabled(f"{panel} [data-role=set-factor]")
    b.page.click(f"{panel} [data-role=pause]")
    b.page.wait_for_selector(f'{panel} [data-role=clock-paused]:has-text("paused")')
    assert ms.clock("rt").paused
    b.page.click(f"{panel} [data-role=pause]")
    b.page.wait_for_selector(f'{panel} [data-role=clock-paused]:has-text("running")')
    assert not ms.clock("rt").paused
    b.page.click(f"{panel} [data-role=switch-mode]")
    b.page.wait_for_selector(f'{panel} [data-role=clock-mode]:has-text("virtual")')
    assert ms.clock("rt").mode == "virtual"
    assert b.page.is_enabled(f"{panel} [data-role=advance]")
    assert b.page.is_disabled(f"{panel} [data-role=set-factor]")
    t = ms.clock("rt").t
    b.page.fill(f'{panel} input[aria-label="seconds to advance"]', "0.25")
    b.page.click(f"{panel} [data-role=advance]")
    b.page.wait_for_selector(f'{panel} [data-role=clock-t]:has-text("{t + 0.25:.4f}")')
    ms.delete_controller("rt")


def test_a_controller_deleted_and_created_again_is_shown_from_its_new_log(browser, ms):
    """Its old stream ends (4410, or on resume the service answers ``reset`` for the stale
    epoch); the page starts the new log from its first event, with nothing of the old one."""
    b = browser
    ms.create_controller("pmac", id="again", clock="virtual")
    ms.define_rotary("again", 1, 600)
    ms.load_lines("again", 1, ["TM20 X1"] * 8)
    b.page.wait_for_selector('[data-tab="again"]')
    select(b, "again")
    old = caught_up(b, ms, "again")
    ms.delete_controller("again")
    stream_rotary(ms, "again", lines=12, until_s=0.05)
    b.page.wait_for_function(
        """([want]) => {
             const el = document.querySelector('[data-controller="again"] [data-role=stream]');
             return el && el.isConnected && el.dataset.state === "live"
                    && Number(el.dataset.received) === Number(el.dataset.lastSeq)
                    && Number(el.dataset.lastSeq) >= want; }""",
        arg=[server_last_seq(ms, "again")])
    new = status(b.page, "again")
    assert new["epoch"] != old["epoch"]
    assert (new["gaps"], new["duplicates"]) == ("0", "0")
    assert int(new["lastSeq"]) == server_last_seq(ms, "again")
    ms.set_clock("again", paused=True)
    caught_up(b, ms, "again")
    pr = ms.coord("again", 1)["rotary"]["lines_ahead"]
    assert shown(b, "again", "#cs-1 [data-role=lines-ahead]") == str(pr)
    ms.delete_controller("again")


def test_no_script_errors(browser):
    assert browser.errors == []
