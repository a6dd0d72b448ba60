"""A motionsim service running in a background thread of the current process.

For tests and benches that want a real server on 127.0.0.1 without a subprocess: the service
runs on its own asyncio event loop in one thread (the simulation still sees one loop, no
locks); the caller talks to it over HTTP / WebSocket / TCP like any client.

    with EmbeddedService(Settings(clock={"mode": "virtual"})) as svc:
        MotionSimClient(svc.url).controllers()
"""

from __future__ import annotations

import gc
import threading
from typing import Any

from .settings import Settings
from .sockets import bind_tcp


class EmbeddedService:
    """Serve ``settings`` on ``127.0.0.1`` (``settings.port`` 0 = a free port).

    Attributes (after :meth:`start`): ``url``, ``port``, ``ports`` (protocol name -> port of
    each protocol listener started), ``app`` (the FastAPI app; touch its state only from
    the service's thread).
    """

    def __init__(self, settings: Settings | None = None) -> None:
        self.settings = settings if settings is not None else Settings(port=0)
        self.ports: dict[str, int] = {}
        self.url = ""
        self.port = 0
        self.app: Any = None
        self._server: Any = None
        self._thread: threading.Thread | None = None
        self._ready = threading.Event()
        self._error: BaseException | None = None

    def start(self, timeout: float = 20.0) -> EmbeddedService:
        import uvicorn

        from ..api.main import create_app
        from .http_server import freeze_startup_heap, run_service, uvicorn_config

        sock = bind_tcp(self.settings.host, self.settings.port)
        self.port = sock.getsockname()[1]
        self.settings = self.settings.model_copy(update={"port": self.port})
        self.url = f"http://{self.settings.host}:{self.port}"
        self.app = create_app(self.settings)
        config = uvicorn_config(self.app, self.settings, graceful_s=1)
        self._server = uvicorn.Server(config)

        async def main() -> None:
            from .listeners import start_listeners

            try:
                listeners = await start_listeners(self.app.state.registry, self.settings,
                                                  out=lambda line: None)
                self.ports = {ls.protocol: ls.port for ls in listeners}
                self.app.state.listeners.extend(ls.server for ls in listeners)
            except BaseException as exc:
                self._error = exc
                self._ready.set()
                sock.close()
                raise
            self._ready.set()
            freeze_startup_heap()
            await self._server.serve(sockets=[sock])

        def run() -> None:
            try:
                run_service(main(), self.settings.event_loop)
            except BaseException as exc:  # reported by start()
                self._error = self._error or exc
                self._ready.set()

        self._thread = threading.Thread(target=run, name="motionsim-embedded", daemon=True)
        self._thread.start()
        self._ready.wait(timeout)
        deadline = threading.Event()
        waited = 0.0
        while self._error is None and not self._server.started and waited < timeout:
            deadline.wait(0.01)
            waited += 0.01
        if self._error is not None:
            raise RuntimeError(f"motionsim did not start: {self._error}") from self._error
        if not self._server.started:
            self.stop()
            raise RuntimeError("motionsim did not start in time")
        return self

    def stop(self, timeout: float = 10.0) -> None:
        if self._server is not None:
            self._server.should_exit = True
        if self._thread is not None:
            self._thread.join(timeout)
            self._thread = None
            # the process is the caller's (a test session): what start froze may be freed
            # again once it is garbage (another embedded service only loses the speed-up)
            gc.unfreeze()

    def __enter__(self) -> EmbeddedService:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()


__all__ = ["EmbeddedService"]
