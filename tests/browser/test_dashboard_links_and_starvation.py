"""The dashboard, round 2, in a real browser: deep links open a controller's tab; one labelled
simulated time; starvations counted and timed on the card, host writes marked on the chart,
the legend says "starved"; labels drawn above the traces; ticks at round values; the time
axis names its unit."""

from __future__ import annotations

import re

import pytest

from tests.browser.conftest import dashboard
from tests.browser.page import caught_up, select, shown
from tests.browser.scenario import stream_rotary

pytestmark = pytest.mark.timeout(240)

PMAC = "deep"
CHART = f'[data-controller="{PMAC}"] #cs-2 svg[data-role=rotary-chart]'


@pytest.fixture(scope="module")
def streamed(served, ms):
    """A PMAC whose &1 is streamed and whose &2 ran its nine lines and then waits (starved)."""
    stream_rotary(ms, PMAC, lines=40, until_s=0.8, cs2_lines=9)
    return ms


def _computed(b, selector: str, *props: str) -> list[str]:
    """Computed style ``props`` of the first element matching ``selector``, read in one
    synchronous step on an element in the document: the charts are redrawn every frame, and
    an element replaced between finding it and reading it has no computed style ("")."""
    return b.page.wait_for_function(
        """([sel, props]) => { const el = document.querySelector(sel);
            if (!el || !el.isConnected) return null;
            const st = getComputedStyle(el), out = props.map((p) => st[p]);
            return out.some((v) => v === "") ? null : out; }""",
        arg=[selector, list(props)], timeout=30_000).json_value()


def _numbers(texts: list[str]) -> list[float]:
    return [float(t) for t in texts]


@pytest.mark.parametrize("path", [f"/dashboard?controller={PMAC}", f"/dashboard#{PMAC}"])
def test_a_deep_link_opens_that_controllers_tab(served, streamed, path):
    with dashboard(served, path, route_sockets=False) as b:
        b.page.wait_for_selector(f'main [data-controller="{PMAC}"]')
        assert b.page.locator(f'[data-tab="{PMAC}"].on').count() == 1
        assert b.page.evaluate("location.hash") == f"#{PMAC}"   # the address names the tab
        b.page.click('[data-tab="pmac"] button.pick')
        b.page.wait_for_selector('main [data-controller="pmac"]')
        assert b.page.evaluate("location.hash") == "#pmac"
        assert b.errors == []


def test_the_hash_switches_tabs_in_a_page_already_open(served, streamed):
    with dashboard(served, "/dashboard", route_sockets=False) as b:
        b.page.wait_for_selector('[data-tab="trio"]')
        b.page.evaluate("location.hash = '#trio'")
        b.page.wait_for_selector('main [data-controller="trio"]')


def test_a_deep_link_to_a_missing_controller_says_so_and_shows_no_other(served, streamed):
    """Issue 36 item 5: an unknown deep link silently showed another controller."""
    with dashboard(served, "/dashboard#nosuch", route_sockets=False) as b:
        b.page.wait_for_selector('[data-tab="pmac"]')
        note = b.page.wait_for_selector("main [data-role=missing]")
        assert 'No controller "nosuch"' in note.inner_text()
        assert b.page.locator("main [data-controller]").count() == 0
        assert b.page.locator("[data-tab].on").count() == 0
        assert b.page.evaluate("location.hash") == "#nosuch"
        b.page.click('[data-tab="trio"] button.pick')  # the user's click wins
        b.page.wait_for_selector('main [data-controller="trio"]')
        assert b.errors == []


def test_one_labelled_simulated_time(browser, streamed):
    b = browser
    select(b, PMAC)
    caught_up(b, streamed, PMAC)
    b.page.wait_for_timeout(700)  # a poll of the clock
    t = streamed.clock(PMAC).t
    line = shown(b, PMAC, ".clock-line")
    assert line.startswith(f"simulated time {t:.4f} s")
    status = shown(b, PMAC, "[data-role=stream]")
    assert " t = " not in status and "model t" not in status   # no second, unlabelled time
    times = re.findall(r"\d+\.\d{4} s", b.page.inner_text(f'[data-controller="{PMAC}"]'))
    assert times == [f"{t:.4f} s"]


def test_starvations_are_counted_and_timed_on_the_card(browser, streamed):
    b = browser
    caught_up(b, streamed, PMAC)
    states = [e for e in streamed.all_events(PMAC, types=["program"]) if e["cs"] == 2]
    waits = [e["t"] for e in states if e["state"] == "waiting"]
    assert len(waits) == 1
    t = streamed.clock(PMAC).t
    assert shown(b, PMAC, "#cs-2 [data-role=starved-count]") == "1×"
    assert shown(b, PMAC, "#cs-2 [data-role=starved-total]") == f"{t - waits[0]:.3f} s"
    assert shown(b, PMAC, "#cs-1 [data-role=starved-count]") == "0×"
    legend = shown(b, PMAC, "#cs-2 .legend")
    assert "starved" in legend and "host write" in legend


def test_host_writes_are_marked_on_the_chart(browser, streamed):
    b = browser
    caught_up(b, streamed, PMAC)
    loads = streamed.all_events(PMAC, types=["line_loaded"])
    writes_cs1 = sorted({e["t"] for e in loads if e["cs"] == 1})
    marks = b.page.eval_on_selector_all(
        f'[data-controller="{PMAC}"] #cs-1 svg line.host-write', "els => els.map(e => e.dataset.t)")
    # one mark a pixel column: every write shown, or merged into the mark of its column
    assert 1 <= len(marks) <= len(writes_cs1)
    assert set(_numbers(marks)) <= set(writes_cs1)
    assert float(marks[0]) == writes_cs1[0]


def test_starved_shading_reads_at_100_percent(browser, streamed):
    """The shading's opacity against white must give a visible colour: at least 0.2."""
    b = browser
    # one synchronous read of an element in the document: the chart is redrawn every frame,
    # and a rect replaced between finding it and reading it has no computed style ("")
    (opacity,) = _computed(b, f"{CHART} rect.starved", "opacity")
    assert float(opacity) >= 0.2


def test_labels_are_drawn_above_the_traces_with_a_halo(browser, streamed):
    b = browser
    caught_up(b, streamed, PMAC)
    b.page.wait_for_selector(f'[data-controller="{PMAC}"] #cs-1 svg text.level-text.i17',
                             state="attached")   # I16 / I17 come with the page's first poll
    order = b.page.eval_on_selector(
        f'[data-controller="{PMAC}"] #cs-1 svg[data-role=rotary-chart]',
        """svg => [...svg.children].map((el) => el.getAttribute('class') || el.tagName)""")
    trace = order.index("trace ahead")
    labels = [i for i, cls in enumerate(order) if cls.startswith("level-text")]
    assert labels and min(labels) > trace
    halo = _computed(b, f'[data-controller="{PMAC}"] #cs-1 svg text.level-text',
                     "paintOrder", "stroke")
    assert halo[0].startswith("stroke") and halo[1] in ("rgb(255, 255, 255)", "#fff")


def test_ticks_are_round_values_and_the_time_axis_names_its_unit(browser, streamed):
    b = browser
    svg = f'[data-controller="{PMAC}"] #cs-1 svg[data-role=rotary-chart]'
    values = _numbers(b.page.eval_on_selector_all(f"{svg} text[data-tick]",
                                                  "els => els.map(e => e.dataset.tick)"))
    step = values[1] - values[0]
    assert values[0] == 0
    assert all(b - a == step for a, b in zip(values, values[1:], strict=False))
    assert step / 10 ** int(f"{step:e}".split("e")[1]) in (1, 2, 5)
    assert max(values) >= 10                                      # I17 fits under the top
    times = _numbers(b.page.eval_on_selector_all(f"{svg} text.tick.mid, {svg} text.tick.start",
                                                 "els => els.map(e => e.textContent)"))
    t_step = round(times[1] - times[0], 9)
    assert round(t_step / 10 ** int(f"{t_step:e}".split("e")[1]), 9) in (1, 2, 5)
    assert all(round(t / t_step, 6) == round(t / t_step) for t in times)
    assert b.page.text_content(f"{svg} [data-role=time-unit]") == "t (s)"


def test_a_trio_axis_counts_and_times_its_stalls(browser, ms):
    """TN20-16: axis 0 stalls while its process waits behind axis 1's move; its row says how
    often and for how long in all (the stalled intervals of the page's own model)."""
    from tests.browser.scenario import run_tn20

    b = browser
    run_tn20(ms, "tn", seconds=0.3)
    b.page.wait_for_selector('[data-tab="tn"]')
    select(b, "tn")
    caught_up(b, ms, "tn")
    b.page.wait_for_timeout(700)
    text = b.page.text_content('[data-controller="tn"] [data-axis="0"] [data-role=stalled]')
    m = re.fullmatch(r"stalled (\d+)× (\d+\.\d{3}) s", text)
    assert m and int(m[1]) >= 1 and float(m[2]) > 0.05, text
    spans = b.page.evaluate("""() => {
        const a = window.motionsimDashboard.controllers.get('tn').model.axes.get(0);
        return [a.stalls, a.stalledTotal(0.3)]; }""")
    assert spans[0] == int(m[1]) and abs(spans[1] - float(m[2])) < 1e-3
    axis1 = b.page.text_content('[data-controller="tn"] [data-axis="1"] [data-role=stalled]')
    assert axis1 == "stalled 0× 0.000 s"

