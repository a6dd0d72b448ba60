"""A host that streams a program into a 600-word rotary buffer, driven by BREQ interrupts.

Run: ``.venv/bin/python examples/pmac/breq_host.py``. The host sends one line per BREQ rising
edge (every line loaded below I17 pulses BREQ) and sleeps while BREQ stays low (I17 or more
lines ahead) until calculation brings the count below I16. Prints a short BREQ timeline.
"""

from __future__ import annotations

from motionsim.sim.pmac import PmacController


def main(n_lines: int = 40) -> None:
    c = PmacController("pmac", {"i16": 5, "i17": 10})
    for line in ("&1 DEFINE ROT 600", "&1 B0", "OPEN ROT"):
        reply = c.terminal(line)
        while not reply.done:
            c.env.step()
    c.terminal("CLOSE")
    c.run(1)
    rot = c.coord_system(1).rotary

    def host():
        yield c.env.timeout(0.01)
        for i in range(n_lines):
            if not rot.breq:
                yield c.wait_breq(1)
            c.load_lines(1, [f"TM20 TA10 TS0 X{i + 1}"])

    c.env.process(host())
    c.env.run(until=2.0)
    period = c.scheduler.period_s
    for e in c.log.events("breq", "program"):
        print(f"cycle {round(e.t / period):5d}  {e.type:8s} {dict(e.fields)}")
    print(f"moves executed: {len(c.log.events('move_end'))}, PR now {rot.lines_ahead}")


if __name__ == "__main__":
    main()
