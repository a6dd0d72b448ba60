"""An HMI pointed at ``motionsim serve --modbus-port auto``: the real pymodbus client reads the
Trio's inputs and outputs and switches its outputs over Modbus TCP.

Trio's "MODBUS TCP/IP" product page (Ethernet daughter board): function 1 and 2 "reads Trio IO",
5 "Force Single Coil (write to a Trio Output)"; the TRM's Modbus code table (M216-522/523):
1 and 2 return the I/O bit pattern for channels 0..NIO-1, 5 sets ``OP(n, ON/OFF)`` for
n = 8..NIO-1. Function 15 (a block of coils) is served the same way ``[INF]``.
"""

from __future__ import annotations

import httpx

from tests.integration.test_clients_pmac import motionsim_serve


def _put(http: str, name: str, value: float) -> None:
    r = httpx.put(f"{http}/controllers/trio/variables/{name}", json={"value": value}, timeout=10)
    assert r.status_code == 200, r.text


def _get(http: str, name: str) -> float:
    return httpx.get(f"{http}/controllers/trio/variables/{name}", timeout=10).json()["value"]


def _terminal(http: str, command: str) -> dict:
    r = httpx.post(f"{http}/controllers/trio/terminal", json={"command": command}, timeout=10)
    assert r.status_code == 200, r.text
    return r.json()


def test_hmi_lamps_and_buttons_over_modbus_tcp() -> None:
    from pymodbus.client import ModbusTcpClient

    with motionsim_serve("--trio-port", "0", "--modbus-port", "auto") as svc:
        http, port = svc.http, svc.listening["modbus"]
        _put(http, "IN(1)", 1)  # a machine input: guard closed
        _put(http, "IN(4)", 1)
        assert _terminal(http, "OP(10,ON)")["error"] is None  # the program lights a lamp
        client = ModbusTcpClient("127.0.0.1", port=port, timeout=10)
        assert client.connect()
        try:
            inputs = client.read_discrete_inputs(0, count=8)
            lamps = client.read_coils(8, count=8)
            button = client.write_coil(11, True)  # the HMI's button: output 11 ON
            block = client.write_coils(20, [True, True, False, True])
            off = client.write_coil(10, False)
            lamps_after = client.read_coils(8, count=16)
            refused = client.write_coil(2, True)  # channel 2 is an input
            no_fc4 = client.read_input_registers(0, count=1)
        finally:
            client.close()
        assert inputs.bits[:8] == [False, True, False, False, True, False, False, False]
        assert lamps.bits[:8] == [False, False, True, False, False, False, False, False]
        assert not button.isError() and not block.isError() and not off.isError()
        assert lamps_after.bits[:16] == [False] * 3 + [True] + [False] * 8 + [True, True,
                                                                              False, True]
        assert refused.isError() and refused.exception_code == 2
        assert no_fc4.isError() and no_fc4.exception_code == 1
        assert [_get(http, f"OP({n})") for n in (10, 11, 20, 21, 22, 23)] == [
            0.0, 1.0, 1.0, 1.0, 0.0, 1.0]
        # a program sees the HMI's write as its own output state
        assert _terminal(http, "PRINT READ_OP(11)")["reply"].strip().startswith("1")
