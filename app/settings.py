"""Service settings: what ``motionsim serve`` runs.

Built once in ``app/cli.py`` (from defaults, ``MOTIONSIM_*`` environment variables, a
``--config`` YAML/JSON file and the command-line options, later ones winning) and passed to
``motionsim.api.main.create_app(settings)``. Nothing here is created at import time.

The config file has the same fields, e.g.::

    host: 127.0.0.1
    port: 8000
    clock: {mode: virtual}
    pmac_port: 1025          # 0 = disabled, "auto" = a free port (printed)
    modbus_port: 502         # Trio Modbus TCP (VR() registers); default 0 = disabled
    controllers:
      - {id: pmac, kind: pmac, config: {i16: 5, i17: 10}}
      - {id: trio, kind: trio, clock: {mode: realtime, factor: 10}}
    plugins: [mypackage.kinds]   # modules imported first (they may register kinds)
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any, Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, field_validator
from pydantic_settings import BaseSettings, NoDecode, SettingsConfigDict

from ..sim.bounds import CLOCK_FACTOR

#: Default request body limit (bytes); the setting ``max_body_bytes``.
DEFAULT_MAX_BODY_BYTES = 8 * 1024 * 1024

#: The PMAC Ethernet protocol's port, and the Trio command line's (telnet) port.
DEFAULT_PMAC_PORT = 1025
DEFAULT_TRIO_PORT = 23
#: The Trio Modbus TCP slave's port (VR() as holding registers); off unless asked for.
DEFAULT_MODBUS_PORT = 502


class ClockSpec(BaseModel):
    """How a controller's simulated time is driven."""

    model_config = ConfigDict(extra="forbid")

    mode: Literal["virtual", "realtime", "host-paced"] = "realtime"
    factor: float = Field(1.0, ge=CLOCK_FACTOR.low, le=CLOCK_FACTOR.high, allow_inf_nan=False,
                          description="speed-up: simulated seconds per wall second (realtime)")
    paused: bool = False
    reaction_s: float = Field(0.0, ge=0, le=60, allow_inf_nan=False, description=(
        "host-paced: simulated seconds a host takes to react to the event it waited for"))


class ControllerSpec(BaseModel):
    """One controller to create at start-up."""

    model_config = ConfigDict(extra="forbid")

    id: str | None = None
    kind: str
    clock: ClockSpec | None = Field(None, description="default: the service's clock")
    config: dict[str, Any] = Field(default_factory=dict)


ProtocolPort = int | Literal["auto"]


class Settings(BaseSettings):
    """Everything ``motionsim serve`` needs.

    ``controllers`` ``None`` means the embedded defaults: ``pmac`` (kind pmac) and ``trio``
    (kind trio), skipping (with a warning) a kind that is not installed.
    ``pmac_port`` / ``trio_port``: an int port, ``0`` = disabled, ``"auto"`` = a free port;
    ``None`` = the default port (1025 / 23), skipped with one line if it cannot be bound.
    """

    model_config = SettingsConfigDict(env_prefix="MOTIONSIM_", extra="forbid")

    host: str = "127.0.0.1"
    port: int = Field(8000, ge=0, le=65535)
    clock: ClockSpec = Field(default_factory=ClockSpec)
    controllers: list[ControllerSpec] | None = None
    pmac_port: ProtocolPort | None = None
    trio_port: ProtocolPort | None = None
    modbus_port: ProtocolPort | None = Field(
        0, description="Trio Modbus TCP port; 0 (default) = disabled, None = 502")
    pmac_controller: str = "pmac"
    trio_controller: str = "trio"
    event_loop: Literal["auto", "asyncio", "uvloop"] = Field(
        "auto", description="the event loop serving HTTP, WebSocket and the TCP ports: uvloop "
                            "(auto: when installed) or the standard library's asyncio")
    log_capacity: int = Field(100_000, ge=100_000,
                              description="events each controller's log holds")
    plugins: list[str] = Field(default_factory=list,
                               description="modules imported at start (may register kinds)")
    # -- limits (README "What is protected") --------------------------------------------
    max_body_bytes: int = Field(DEFAULT_MAX_BODY_BYTES, ge=1024, le=1 << 30,
                                description="largest request body (413 above)")
    max_controllers: int = Field(64, ge=1, le=10_000,
                                 description="controllers that may exist at once (409 above)")
    tcp_max_connections: int = Field(
        32, ge=1, le=10_000, description="open connections per TCP protocol listener")
    tcp_idle_timeout_s: float = Field(
        600.0, gt=0, le=86_400, allow_inf_nan=False,
        description="a TCP protocol connection that sends nothing this long is closed")
    http_max_connections: int = Field(
        800, ge=1, le=100_000,
        description="HTTP + WebSocket connections open at once; one more is answered 503 and "
                    "closed (keep it under the process's file-descriptor limit)")
    http_header_timeout_s: float = Field(
        10.0, gt=0, le=3600, allow_inf_nan=False,
        description="a request whose headers are not complete this long after the connection "
                    "opened (or the previous response) is answered 408 and closed")
    http_max_header_bytes: int = Field(
        16 * 1024, ge=1024, le=1 << 20,
        description="largest request line + headers (431 and closed above)")
    http_keep_alive_s: int = Field(
        5, ge=1, le=3600, description="an idle HTTP connection between requests is closed "
                                      "after this long (uvicorn timeout_keep_alive)")
    # -- web safety ----------------------------------------------------------------------
    allowed_hosts: Annotated[list[str], NoDecode] = Field(
        default_factory=list,
        description="Host names accepted besides the loopback names and the bound address "
                    "('*' = any); env MOTIONSIM_ALLOWED_HOSTS is comma-separated")
    token: str | None = Field(None, min_length=1, description="bearer token every request "
                              "but GET /health must carry (env MOTIONSIM_TOKEN)")
    cors_origins: Annotated[list[str], NoDecode] = Field(
        default_factory=list, description="origins CORS allows (default none: CORS off); "
                                          "env MOTIONSIM_CORS_ORIGINS is comma-separated")

    @field_validator("allowed_hosts", "cors_origins", mode="before")
    @classmethod
    def _comma_list(cls, v: Any) -> Any:
        if isinstance(v, str):
            return [part.strip() for part in v.split(",") if part.strip()]
        return v

    @field_validator("pmac_port", "trio_port", "modbus_port")
    @classmethod
    def _port_range(cls, v: ProtocolPort | None) -> ProtocolPort | None:
        if isinstance(v, int) and not 0 <= v <= 65535:
            raise ValueError("port must be 0..65535 or 'auto'")
        return v


def load_config_file(path: str | Path) -> dict[str, Any]:
    """Read a YAML (or JSON) settings file into a dict (validated by :class:`Settings`)."""
    p = Path(path)
    text = p.read_text(encoding="utf-8")
    data = json.loads(text) if p.suffix == ".json" else yaml.safe_load(text)
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ValueError(f"{p}: expected a mapping of settings at the top level")
    return data


def build_settings(config_file: str | Path | None = None, **overrides: Any) -> Settings:
    """Defaults < environment < config file < ``overrides`` (``None`` values are ignored)."""
    data: dict[str, Any] = load_config_file(config_file) if config_file else {}
    data.update({k: v for k, v in overrides.items() if v is not None})
    return Settings(**data)


__all__ = [
    "DEFAULT_MODBUS_PORT",
    "DEFAULT_PMAC_PORT",
    "DEFAULT_TRIO_PORT",
    "ClockSpec",
    "ControllerSpec",
    "Settings",
    "build_settings",
    "load_config_file",
]
