"""What ``/openapi.json`` publishes beyond what the route schemas generate (issue 33 item 7).

* **integer bounds as integers**: FastAPI's OpenAPI models hold ``minimum`` / ``maximum`` as
  floats, so an integer field's bounds came out as ``16.0`` and a seed's ``2**63 - 1`` as
  ``9.223372036854776e+18`` (which is 2**63, one past the bound). An integer schema's bounds
  are published as JSON integers again, a float that rounds to 2**63 as ``2**63 - 1`` (the only
  int64 bound it can have been);
* **event types**: the ``type`` of an event (the wire's ``EventOut.type``, the events query's
  ``type`` filter) lists the known types as an ``enum`` — those of
  :data:`motionsim.sim.events.EVENT_FIELDS` and of every registered kind;
* **Trio process numbers by model**: a ``process`` field says its maximum per Trio model
  (``x-maximum-by-model``, and in its description): 1..N where N is the model's processes.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from fastapi import FastAPI

_INT64_MAX = 2**63 - 1


def known_event_types() -> list[str]:
    """Every event type a controller of a registered kind may emit."""
    from ..app.kinds import kinds
    from ..sim.events import EVENT_FIELDS

    types = set(EVENT_FIELDS)
    for kind in kinds().values():
        types.update(getattr(kind, "event_types", ()) or ())
    return sorted(types)


def processes_by_model() -> dict[str, int]:
    from ..sim.trio import MODELS

    return {name: m.processes for name, m in MODELS.items()}


def _int_bound(value: Any) -> Any:
    if isinstance(value, float) and value.is_integer():
        return _INT64_MAX if value >= 2.0**63 else int(value)
    return value


def _walk(node: Any, types: list[str], by_model: dict[str, int], key: str = "") -> None:
    """Integer bounds as integers and the per-model ``process`` maxima, everywhere."""
    if isinstance(node, dict):
        if node.get("type") == "integer":
            for bound in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
                if bound in node:
                    node[bound] = _int_bound(node[bound])
        if key == "process" and ("anyOf" in node or node.get("type") == "integer"):
            node["x-maximum-by-model"] = by_model
            text = ", ".join(f"{m} {n}" for m, n in by_model.items())
            node["description"] = (node.get("description", "") +
                                   f" (Trio processes by model: {text})").strip()
        for k, v in node.items():
            if k == "properties" and isinstance(v, dict):
                for name, sub in v.items():
                    _walk(sub, types, by_model, name)
            elif k == "parameters" and isinstance(v, list):
                for p in v:
                    if isinstance(p, dict) and "schema" in p:
                        _walk(p["schema"], types, by_model, p.get("name", ""))
            else:
                _walk(v, types, by_model)
    elif isinstance(node, list):
        for v in node:
            _walk(v, types, by_model)


#: Schemas whose ``type`` property is an event type. Not ``EventPattern`` (a run-until's
#: pattern): the route does not refuse every type outside the list (a zero timeout answers
#: ``timeout`` first), and a published enum would promise that it does.
_EVENT_SCHEMAS = ("EventOut",)


def _event_types(schema: dict[str, Any], types: list[str]) -> None:
    """``enum`` on the event ``type`` of the event schemas and of the events query."""
    components = schema.get("components", {}).get("schemas", {})
    for name in _EVENT_SCHEMAS:
        prop = components.get(name, {}).get("properties", {}).get("type")
        if isinstance(prop, dict):
            prop["enum"] = types
    for path, ops in schema.get("paths", {}).items():
        if not path.endswith("/events"):
            continue
        for op in ops.values():
            for p in op.get("parameters", []) if isinstance(op, dict) else []:
                if p.get("name") != "type":
                    continue
                for sub in p["schema"].get("anyOf", [p["schema"]]):
                    items = sub.get("items") if isinstance(sub, dict) else None
                    if isinstance(items, dict):
                        items["enum"] = types


def install(app: FastAPI) -> None:
    """``app.openapi`` with the additions above, built once."""
    generate: Callable[[], dict[str, Any]] = app.openapi

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is None or not app.openapi_schema.get("x-motionsim-extras"):
            schema = generate()
            types = known_event_types()
            _walk(schema, types, processes_by_model())
            _event_types(schema, types)
            schema["x-motionsim-extras"] = True
            app.openapi_schema = schema
        return app.openapi_schema

    app.openapi = openapi  # type: ignore[method-assign]


__all__ = ["install", "known_event_types", "processes_by_model"]
