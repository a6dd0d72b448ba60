"""The ``motionsim`` command.

``motionsim serve`` runs the service: REST + WebSocket on ``--port``, the PMAC Ethernet protocol
on ``--pmac-port`` and the Trio command line on ``--trio-port``. Settings come from defaults,
``MOTIONSIM_*`` environment variables, ``--config FILE`` and the options, later ones winning;
they are built here, once, and handed to ``motionsim.api.main.create_app``.
"""

from __future__ import annotations

import socket
import sys
from pathlib import Path
from typing import Annotated, Any

import typer
from pydantic import ValidationError

from . import __version__

cli = typer.Typer(
    name="motionsim",
    help="Simulate Turbo PMAC and Trio Motion Coordinator program buffering as a service. "
         "Point your host software at it instead of the hardware.",
    no_args_is_help=True,
    add_completion=False,
    rich_markup_mode=None,
    pretty_exceptions_enable=False,
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"motionsim {__version__}")
        raise typer.Exit()


@cli.callback()
def _root(
    version: Annotated[bool, typer.Option("--version", callback=_version, is_eager=True,
                                          help="Print the version and exit.")] = False,
) -> None:
    """Simulate Turbo PMAC and Trio Motion Coordinator program buffering as a service."""


def _protocol_port(value: str | None, option: str) -> int | str | None:
    if value is None:
        return None
    if value == "auto":
        return "auto"
    try:
        port = int(value)
    except ValueError:
        raise typer.BadParameter(f"{value!r} is not a port number, 0 or 'auto'",
                                 param_hint=option) from None
    if not 0 <= port <= 65535:
        raise typer.BadParameter(f"{port} is not in 0..65535", param_hint=option)
    return port


def _fail(message: str, code: int) -> typer.Exit:
    typer.echo(f"motionsim: {message}", err=True)
    return typer.Exit(code)


@cli.command()
def serve(
    host: Annotated[str | None, typer.Option(metavar="HOST", help="Interface for every listener. "
                                             "[default: 127.0.0.1]")] = None,
    port: Annotated[int | None, typer.Option(
        metavar="PORT",
        help="REST + WebSocket port; 0 picks a free port (printed). [default: 8000]")] = None,
    clock: Annotated[str | None, typer.Option(
        metavar="realtime|virtual|host-paced",
        help="realtime: simulated time follows the wall clock × factor; virtual: time moves "
             "only when a client advances it (tests); host-paced: virtual time that holds "
             "for hosts registered as holders (API.md). [default: realtime]")] = None,
    factor: Annotated[float | None, typer.Option(
        metavar="FACTOR",
        help="Realtime speed-up: simulated seconds per wall second. [default: 1.0]")] = None,
    pmac_port: Annotated[str | None, typer.Option(
        metavar="PORT",
        help="PMAC Ethernet protocol port for controller 'pmac'; 0 disables, 'auto' picks a "
             "free port. [default: 1025, skipped if it cannot be bound]")] = None,
    trio_port: Annotated[str | None, typer.Option(
        metavar="PORT",
        help="Trio command-line (telnet) port for controller 'trio'; 0 disables, 'auto' picks "
             "a free port. [default: 23, skipped if it cannot be bound]")] = None,
    modbus_port: Annotated[str | None, typer.Option(
        metavar="PORT",
        help="Trio Modbus TCP port (VR() as holding registers, I/O as coils and inputs) for "
             "controller 'trio'; "
             "'auto' picks a free port. [default: 0 = disabled]")] = None,
    config: Annotated[Path | None, typer.Option(
        metavar="FILE", exists=True, dir_okay=False, readable=True,
        help="YAML/JSON settings file: controllers, their kinds, clocks and initial "
             "variables (see README).")] = None,
    plugin: Annotated[list[str] | None, typer.Option(
        metavar="MODULE",
        help="Import this module first (it may register extra controller kinds). "
             "Repeatable.")] = None,
    record: Annotated[Path | None, typer.Option(
        metavar="FILE",
        help="Record every TCP protocol session's bytes to this JSON Lines file (an existing "
             "one is kept as FILE.1, FILE.2, ...).")] = None,
    token: Annotated[str | None, typer.Option(
        metavar="TOKEN",
        help="Require 'Authorization: Bearer TOKEN' (or ?token=) on every request but GET "
             "/health; env MOTIONSIM_TOKEN.")] = None,
    allow_host: Annotated[list[str] | None, typer.Option(
        metavar="HOST",
        help="Also accept requests whose Host header names HOST (besides the loopback names "
             "and the bound address); '*' = any. Repeatable; env MOTIONSIM_ALLOWED_HOSTS.")
    ] = None,
) -> None:
    """Run the simulation service.

    With no options: controllers 'pmac' and 'trio' on a realtime clock at factor 1, REST on
    http://127.0.0.1:8000 (docs at /docs), PMAC Ethernet on 1025, Trio telnet on 23.
    Prints one 'motionsim listening ...' line per listener.
    """
    import logging

    from .settings import build_settings

    logging.basicConfig(level=logging.WARNING, format="motionsim: %(message)s")

    if clock is not None and clock not in ("realtime", "virtual", "host-paced"):
        raise typer.BadParameter("must be 'realtime', 'virtual' or 'host-paced'",
                                 param_hint="--clock")
    from .config_file import ConfigFileError, read_config, where

    try:
        file_data, lines = read_config(config) if config else ({}, {})
    except ConfigFileError as exc:
        typer.echo(str(exc), err=True)  # FILE:LINE:COLUMN: what
        raise typer.Exit(2) from None
    as_written = dict(file_data)
    overrides: dict[str, Any] = {
        "host": host, "port": port,
        "pmac_port": _protocol_port(pmac_port, "--pmac-port"),
        "trio_port": _protocol_port(trio_port, "--trio-port"),
        "modbus_port": _protocol_port(modbus_port, "--modbus-port"),
    }
    if clock is not None or factor is not None:
        clock_data = dict(file_data.get("clock") or {})
        if clock is not None:
            clock_data["mode"] = clock
        if factor is not None:
            clock_data["factor"] = factor
        overrides["clock"] = clock_data
    if plugin:
        overrides["plugins"] = [*file_data.get("plugins", []), *plugin]
    if token is not None:
        overrides["token"] = token
    if allow_host:
        overrides["allowed_hosts"] = [*file_data.get("allowed_hosts", []), *allow_host]
    file_data.update({k: v for k, v in overrides.items() if v is not None})
    try:
        settings = build_settings(None, **file_data)
    except ValidationError as exc:
        from .config_file import dotted

        for e in exc.errors():
            place = where(config, as_written, lines, e["loc"]) if config else None
            typer.echo(f"{place or 'motionsim: invalid settings'}: {dotted(e['loc'])}: "
                       f"{e['msg']}", err=True)
        raise typer.Exit(2) from None

    from .sockets import bind_tcp

    try:
        sock = bind_tcp(settings.host, settings.port)
    except OSError as exc:
        raise _fail(f"cannot listen on http://{settings.host}:{settings.port}: "
                    f"{exc.strerror or exc}", 1) from None
    settings = settings.model_copy(update={"port": sock.getsockname()[1]})

    from ..api.main import create_app
    from ..sim.errors import MotionSimError

    try:
        app = create_app(settings)
    except (MotionSimError, ImportError) as exc:
        sock.close()
        place = _config_key_place(config, as_written, lines, exc) if config else None
        if place is not None:
            typer.echo(f"{place}: {exc}", err=True)
            raise typer.Exit(2) from None
        raise _fail(f"cannot start: {exc}", 2) from None

    recorder = None
    if record is not None:
        from .recorder import Recorder

        try:
            recorder = Recorder(record, {h.id: {"kind": h.kind, "config": h.controller.config}
                                         for h in app.state.registry})
        except (ValueError, OSError) as exc:  # a directory, a file that is not a transcript
            raise _fail(f"--record: {exc}", 2) from None
    from .http_server import run_service

    code = run_service(_serve(app, settings, sock, recorder), settings.event_loop)
    if recorder is not None:
        recorder.close()
    if code:
        raise typer.Exit(code)


def _config_key_place(config: Path, data: dict[str, Any], lines: Any,
                      exc: BaseException) -> str | None:
    """``FILE:LINE: controllers[i].config.KEY`` of the controller config key a kind refused
    (its error names the key as ``field``), when the settings file has it."""
    from .config_file import dotted, where

    key = getattr(exc, "details", {}).get("field")
    for i, spec in enumerate(data.get("controllers") or []):
        if isinstance(spec, dict) and isinstance(spec.get("config"), dict) \
                and key in spec["config"]:
            loc = ("controllers", i, "config", key)
            place = where(config, data, lines, loc)
            return f"{place}: {dotted(loc)}" if place else None
    return None


async def _serve(app: Any, settings: Any, sock: socket.socket, recorder: Any) -> int:
    """Start the protocol listeners, then serve HTTP on ``sock``; the exit code."""
    import uvicorn

    from .http_server import freeze_startup_heap, uvicorn_config
    from .listeners import ListenerError, start_listeners

    app.state.ready = False
    kwargs = {"recorder": recorder} if recorder is not None else {}
    try:
        listeners = await start_listeners(app.state.registry, settings,
                                        out=lambda line: print(line, flush=True), **kwargs)
    except ListenerError as exc:
        print(f"motionsim: {exc}", file=sys.stderr, flush=True)
        sock.close()
        return 1
    app.state.listeners.extend(listener.server for listener in listeners)
    app.state.ready = True
    config = uvicorn_config(app, settings, graceful_s=2)
    server = uvicorn.Server(config)
    host = f"[{settings.host}]" if ":" in settings.host else settings.host
    print(f"motionsim listening http://{host}:{settings.port}", flush=True)
    freeze_startup_heap()
    await server.serve(sockets=[sock])
    return 0 if server.started else 3


@cli.command()
def replay(
    file: Annotated[Path, typer.Argument(metavar="FILE", exists=True, dir_okay=False,
                                         help="A transcript written by serve --record.")],
) -> None:
    """Replay a wire transcript against fresh controllers; exit 1 if any answer differs."""
    from .replay import main as replay_main

    code = replay_main(file)
    if code:
        raise typer.Exit(code)


@cli.command()
def check(
    files: Annotated[list[Path], typer.Argument(
        metavar="FILE|DIR...", exists=True, readable=True,
        help="PMAC files (.pmc, .pmac, .pma, .plc ...), Trio BASIC programs (.bas) and "
             "libraries (.bal), or folders: every such file below them, in one run (files "
             "another one #includes are checked where they are included; a Trio INCLUDE "
             "\"NAME\" is NAME.bas given here, beside the program or found with -I).")],
    kind: Annotated[str | None, typer.Option(
        metavar="pmac|trio", help="Controller kind [default: trio for .bas, else pmac].")
    ] = None,
    model: Annotated[str | None, typer.Option(
        metavar="MODEL",
        help="Trio model (series2, mc2xx, mc4xx, mc6xx); the PMAC is a Turbo PMAC.")] = None,
    include: Annotated[list[Path] | None, typer.Option(
        "--include", "-I", metavar="DIR",
        help="Search DIR for #include files (PMAC) and INCLUDEd programs / .bal libraries "
             "(Trio). Repeatable.")
    ] = None,
    dialect: Annotated[str, typer.Option(
        metavar="auto|pewin|diamond|msi",
        help="The PMAC downloader's preprocessing: pewin (PEWIN32 / PComm32: ; // /* */ "
             "comments, #define in any case, #include \"f\" or <f>), diamond (Diamond's "
             ".pmc preprocessor), msi (EPICS $(NAME) / ${NAME} from -D, then diamond's); "
             "auto picks per file.")] = "auto",
    define: Annotated[list[str] | None, typer.Option(
        "--define", "-D", metavar="NAME=VALUE",
        help="A macro value (msi) or a predefined #define (pewin, diamond). Repeatable.")
    ] = None,
    format_: Annotated[str, typer.Option(
        "--format", metavar="text|json", help="text: FILE:LINE:COLUMN: ...; json: a list of "
        "findings (file, line, column, severity, code, message, text, cause, more).")
    ] = "text",
) -> None:
    """Load each file into a fresh simulated card and print every line it would refuse
    (FILE:LINE:COLUMN: error: ERRnnn meaning) and every valid line motionsim does not simulate
    (warning); refusals that follow from an earlier one (a failed OPEN, a missing include, an
    undefined macro) are counted under it. Exit status 1 when there is an error, 2 when a
    file cannot be checked."""
    import json

    from ..sim.errors import MotionSimError
    from .check import check_file, grouped, tree_files
    from .pmac_download import DIALECT_NAMES

    if kind is not None and kind not in ("pmac", "trio"):
        raise typer.BadParameter("must be 'pmac' or 'trio'", param_hint="--kind")
    if kind == "pmac" and model is not None:
        raise typer.BadParameter("the PMAC is a Turbo PMAC: --model names a Trio model",
                                 param_hint="--model")
    if format_ not in ("text", "json"):
        raise typer.BadParameter("must be 'text' or 'json'", param_hint="--format")
    if dialect not in DIALECT_NAMES:
        raise typer.BadParameter(f"must be one of {', '.join(DIALECT_NAMES)}",
                                 param_hint="--dialect")
    defines: dict[str, str] = {}
    for item in define or ():
        name, eq, value = item.partition("=")
        if not eq or not name.strip():
            raise typer.BadParameter(f"{item!r}: expected NAME=VALUE", param_hint="-D")
        defines[name.strip()] = value
    findings = []
    failed = []
    paths = tree_files(files, include or (), dialect, defines)
    for path in paths:
        try:
            findings += grouped(check_file(path, kind, model, include or (), dialect,
                                           defines, siblings=paths))
        except (OSError, ValueError, MotionSimError) as exc:
            failed.append(f"{path}: {exc}")
        except Exception as exc:  # noqa: BLE001 - one file's failure must not end the tree's report
            failed.append(f"{path}: cannot be checked: {type(exc).__name__}: {exc} "
                          "(a motionsim bug: please report it with the file)")
    if format_ == "json":
        typer.echo(json.dumps([f.to_dict() for f in findings], indent=1))
    else:
        for finding in findings:
            typer.echo(str(finding))
    for message in failed:
        typer.echo(f"motionsim: {message}", err=True)
    if failed:
        raise typer.Exit(2)
    if any(f.severity == "error" for f in findings):
        raise typer.Exit(1)


@cli.command()
def examples(
    dest: Annotated[Path, typer.Argument(
        metavar="DIR", help="Folder to copy the examples into.")] = Path("motionsim-examples"),
    force: Annotated[bool, typer.Option(
        "--force", help="Copy into DIR even if it already has files (same names replaced).")
    ] = False,
) -> None:
    """Copy the examples shipped with motionsim (scenarios, PMAC and Trio programs, host and
    pytest examples; README.md lists them) into DIR, so an installed motionsim has them too."""
    import shutil
    from importlib.resources import as_file, files

    if dest.exists() and any(dest.iterdir()) and not force:
        raise _fail(f"{dest} is not empty; choose another folder or pass --force", 2)
    with as_file(files("motionsim.examples")) as src:
        shutil.copytree(src, dest, dirs_exist_ok=True,
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "__init__.py"))
    typer.echo(f"copied the examples to {dest}; start with {dest / 'README.md'}")


# What-if scenarios: `motionsim run` and `motionsim sweep` (app/scenarios/cli.py).
from .scenarios.cli import register as _register_scenarios  # noqa: E402

_register_scenarios(cli)


def main() -> None:
    """Console-script entry point."""
    cli()


__all__ = ["cli", "main", "serve"]
