"""What the EPICS ``pmac`` driver polls every cycle (DiamondLightSource/pmac @ 3d2e73f,
``pmacController::setupBrokerVariables``, ``pmacAxis`` constructor, ``pmacCSAxis``,
``pmacHardwareTurbo::setupCSStatus``; spec §5.3): the *pre-fast* request (CS status words and
the trajectory-scan status, read first so a motor that just stopped is seen stopped) and the
*fast* request (global status, CPU-load M-variables, trajectory index / buffer / points, and
per motor ``#nP #nF i{n}24 #n?``, per CS axis ``&cQ8a``), each sent as one space-joined line
of at most 40 items, one reply line per item."""

from __future__ import annotations

MAX_ITEMS = 40


def prefast(cs: int) -> list[str]:
    return [*(f"&{c}??" for c in range(1, cs + 1)), "M4034"]


def fast(motors: int, cs: int, cs_axes: int = 2) -> list[str]:
    items = ["???", "M70", "M71", "M72", "M73", "M4039", "M4040", "M4038"]
    for n in range(1, motors + 1):
        items += [f"#{n}P", f"#{n}F", f"i{n}24", f"#{n}?"]
    for c in range(1, cs + 1):
        items += [f"&{c}Q8{a}" for a in range(1, cs_axes + 1)]
    return items


def requests(motors: int = 8, cs: int = 2) -> list[str]:
    """The poll lines of one cycle, as the broker batches them."""
    out = []
    for items in (prefast(cs), fast(motors, cs)):
        for k in range(0, len(items), MAX_ITEMS):
            out.append(" ".join(items[k:k + MAX_ITEMS]))
    return out
