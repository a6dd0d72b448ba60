"""PMAC PLC programs 0-31: state, scans, last scan time; program text in, as one string."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field


class PlcPublic(BaseModel):
    plc: int = Field(description="0 = foreground (every RTI); 1-31 = background")
    state: Literal["running", "enabled", "disabled", "open", "stopped"] = Field(
        description="running: enabled and permitted by I5; enabled: enabled but I5 forbids "
        "its class; open: being entered (OPEN PLC); stopped: the watchdog tripped"
    )
    enabled: bool
    lines: int = Field(description="program lines stored")
    scans: int = Field(description="scans since the program was stored / power-on")
    last_scan_t: float | None = Field(description="simulated time of the last scan")
    last_scan_statements: int = Field(description="statements executed by the last scan")
    last_send: str | None = Field(description='text of the last SEND"..."')
    compiled: bool = Field(
        default=False, description="a compiled PLC (PLCC n, in `compiled_plcs`); its `lines` "
        "count the source lines downloaded, which the card does not keep (no LIST PLCC)")


class PlcDetail(PlcPublic):
    program: list[str] = Field(description="the stored program, one line each")


class PlcList(BaseModel):
    i5: int = Field(description="I5: 0 none, 1 PLC 0 only (default), 2 PLCs 1-31 only, 3 both")
    plcs: list[PlcPublic] = Field(description="PLCs that hold a program, are enabled or open")
    compiled_plcs: list[PlcPublic] = Field(
        default_factory=list,
        description="compiled PLCs (OPEN PLCC n) that hold a program, are enabled or open")


class PlcProgramIn(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)

    text: str = Field(max_length=200_000, description="PLC program, one statement line per line")


__all__ = ["PlcDetail", "PlcList", "PlcProgramIn", "PlcPublic"]
