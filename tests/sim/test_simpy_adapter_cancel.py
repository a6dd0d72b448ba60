"""Cancelling a wake-up goes through the adapter (``cancel`` / ``pending``): the event stays on
SimPy's queue and is processed at its instant as a no-op; a cancelled wake-up is not re-used."""

import simpy
from motionsim.sim.simpy_adapter import cancel, pending, wake_at


def test_a_cancelled_wake_calls_nothing_and_is_not_pending():
    env = simpy.Environment()
    calls: list[float] = []
    w = wake_at(env, 1.0, lambda ev: calls.append(env.now))
    assert pending(w)
    cancel(w)
    assert not pending(w)
    cancel(w)  # twice: nothing more to do
    env.run()
    assert calls == []
    assert not pending(w)


def test_cancel_and_pending_take_none_and_processed_events():
    env = simpy.Environment()
    assert not pending(None)
    cancel(None)
    calls: list[float] = []
    w = wake_at(env, 1.0, lambda ev: calls.append(env.now))
    env.run()
    assert calls == [1.0] and not pending(w)
    cancel(w)  # processed: nothing to cancel, and it can still be re-used
    assert wake_at(env, 2.0, lambda ev: calls.append(env.now), w) is w
    env.run()
    assert calls == [1.0, 2.0]


def test_a_cancelled_wake_is_not_reused():
    env = simpy.Environment()
    calls: list[float] = []
    w = wake_at(env, 1.0, lambda ev: calls.append(env.now))
    cancel(w)
    again = wake_at(env, 0.5, lambda ev: calls.append(env.now), w)
    assert again is not w
    env.run()
    assert calls == [0.5]


def test_only_the_adapter_touches_an_events_callbacks():
    """DESIGN.md: SimPy internals stay behind sim/simpy_adapter.py; cancelling is its
    ``cancel``, asking is its ``pending``."""
    import ast
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    bad = []
    for folder in ("sim", "app", "api"):
        for path in sorted((root / folder).rglob("*.py")):
            if path.name == "simpy_adapter.py" and path.parent.name == "sim":
                continue
            tree = ast.parse(path.read_text(encoding="utf-8"))
            bad += [
                f"{path.relative_to(root)}:{node.lineno}"
                for node in ast.walk(tree)
                if isinstance(node, ast.Attribute) and node.attr == "callbacks"
            ]
    assert bad == []
