"""The dashboard's recording drawing (``api/static/dashboard/js/recording.js``) run by Node
on a real gather page from ``GET /controllers/{id}/gather``: the samples a zoom span selects
are exactly those with ``t0 <= t <= t1``, and a trace keeps each pixel column's lowest and
highest sample (at most two vertices a column). The browser test (tests/browser/
test_dashboard_recording.py) checks what the page shows."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from tests.api.test_recordings import P, gather_jog

pytestmark = pytest.mark.anyio

JS = Path(__file__).resolve().parents[2] / "api" / "static" / "dashboard" / "js"

SCRIPT = """
import * as r from "%(js)s/recording.js";
import { TimeAxis } from "%(js)s/chart.js";
const page = JSON.parse(await new Promise((ok) => {
  let s = ""; process.stdin.on("data", (c) => s += c); process.stdin.on("end", () => ok(s));
}));
const t = page.columns.t;
const [t0, t1] = [t[Math.floor(t.length / 4)], t[Math.floor(t.length / 2)]];
const [a, b] = r.spanIndices(t, t0, t1);
const ax = new TimeAxis(t0, t1, 40, 240);
const out = { t0, t1, a, b, traces: [] };
for (const tr of r.traces(page)) {
  const [lo, hi] = r.valueRange(tr.v, a, b);
  const { d, vertices } = r.linePath(tr, a, b, ax, (w) => w);   // y = the value itself
  out.traces.push({ name: tr.name, lo, hi, vertices,
                    ys: [...d.matchAll(/[ML][\\d.]+ (-?[\\d.e+]+)/g)].map((m) => Number(m[1])) });
}
console.log(JSON.stringify(out));
"""


async def test_zoom_span_and_trace_vertices_of_a_real_gather(pmac_api):
    node = shutil.which("node")
    if node is None:
        pytest.fail("node is needed to run the dashboard's drawing code")
    await gather_jog(pmac_api)
    page = (await pmac_api.get(f"{P}/gather", params={"limit": 100_000})).json()
    run = subprocess.run([node, "--input-type=module", "-e", SCRIPT % {"js": JS}],
                         input=json.dumps(page), capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    t = page["columns"]["t"]
    assert t[out["a"]:out["b"]] == [x for x in t if out["t0"] <= x <= out["t1"]]
    for tr in out["traces"]:
        values = page["columns"][tr["name"]][out["a"]:out["b"]]
        assert tr["vertices"] <= 2 * 201
        assert min(tr["ys"]) == pytest.approx(min(values), abs=0.06)
        assert max(tr["ys"]) == pytest.approx(max(values), abs=0.06)
