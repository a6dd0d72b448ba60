"""The REST move (``TrioController.move``, POST /controllers/{id}/axes/{n}/move) and a BASIC
line build the same move: one home, sim/trio/motion/issue.py. A move issued either way, on a
fresh controller with the same settings, leaves the same event log apart from the command's
text (SP moves at the FORCE_SPEED of the moment they are issued, spec trio.md §10.2 ``[BK]``)."""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import make, run_to


def _log(c) -> list[tuple[float, str, dict]]:
    return [(e.t, e.type, {k: v for k, v in e.fields.items() if k != "text"})
            for e in c.log.events()]


@pytest.mark.parametrize("kind, args", [
    ("MOVE", [25.0]), ("MOVEABS", [40.0, -10.0]), ("MOVESP", [30.0]), ("FORWARD", []),
])
def test_rest_and_basic_issue_the_same_move(kind, args):
    def issue(rest: bool):
        c = make()
        reply = c.terminal("FORCE_SPEED AXIS(0) = 500")
        assert reply.done and not reply.error and c.axes[0].force_speed == 500.0
        if rest:
            c.move(0, kind, args)
        else:
            text = f"{kind}({','.join(f'{a:g}' for a in args)}) AXIS(0)" if args else \
                f"{kind} AXIS(0)"
            reply = c.terminal(text)
            assert reply.done and not reply.error, reply.error
        run_to(c, 0.2)
        return _log(c)

    rest, basic = issue(True), issue(False)
    assert any(t == "move_start" for _t, t, _f in rest)
    assert rest == basic
