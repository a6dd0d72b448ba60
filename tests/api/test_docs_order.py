"""``/docs`` opens on what a session needs first and says where to look (issue 36 item 5: it
opened on Trio axes before controllers and clock and linked neither the dashboard nor API.md)."""

from __future__ import annotations

from motionsim.api.main import create_app


def test_the_route_groups_come_in_the_documented_order_and_each_is_listed():
    spec = create_app().openapi()
    order = [t["name"] for t in spec["tags"]]
    assert order[:3] == ["service", "controllers", "clock"]
    assert order.index("trio axes") > order.index("coord")
    used = {tag for path in spec["paths"].values() for op in path.values()
            for tag in op.get("tags", [])}
    assert used <= set(order), used - set(order)  # a new group must be placed in the order
    assert all(t.get("description") for t in spec["tags"])


def test_the_docs_link_the_dashboard_and_name_the_contract():
    info = create_app().openapi()["info"]
    assert "(/dashboard)" in info["description"] and "docs/API.md" in info["description"]
