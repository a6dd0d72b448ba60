"""uvicorn's WebSocket protocol, plus one way to send: ready-made frames written at once.

Every ASGI ``websocket.send`` goes through Starlette's ``send_text``, its exception-handler
wrapper, uvicorn's ``send`` (an awaited ``writable`` event, the sans-I/O protocol framing the
text) and then ``transport.write``: tens of microseconds per message, paid per subscriber per
event by the event stream (issue 35's WebSocket fan-out). The stream's text frames are the
same bytes for every subscriber that reads the same events (a server never masks its frames,
RFC 6455 section 5.1, and per-message compression is off: ``ws_per_message_deflate=False``),
so :mod:`motionsim.api.ws_fanout` frames an event once and writes the bytes to each caught-up
subscriber's transport through this protocol's :meth:`FramedWebSocketProtocol.write_frames`.

The protocol offers it to the app as the ASGI scope extension :data:`EXTENSION` (a callable
``write_frames(data) -> bool``), only where it holds: after a completed handshake, with
compression off. Without it (Starlette's test client, another server) the stream sends through
ASGI as before. Closing, pings and the handshake stay uvicorn's.
"""

from __future__ import annotations

from typing import Any

from uvicorn.protocols.websockets.websockets_sansio_impl import WebSocketsSansIOProtocol
from websockets.frames import Frame, Opcode
from websockets.protocol import State

#: The scope extension naming :meth:`FramedWebSocketProtocol.write_frames`.
EXTENSION = "motionsim.ws_frames"


def text_frame(text: str) -> bytes:
    """The bytes of one text message as this server sends it: a final, unmasked,
    uncompressed frame — what uvicorn writes for ``websocket.send`` with ``text``
    (the same serialisation, ``websockets.frames.Frame``)."""
    return Frame(Opcode.TEXT, text.encode()).serialize(mask=False, extensions=[])


class FramedWebSocketProtocol(WebSocketsSansIOProtocol):
    """uvicorn's sans-I/O WebSocket protocol offering :meth:`write_frames` to the app."""

    def handle_connect(self, event: Any) -> None:
        super().handle_connect(event)
        scope = getattr(self, "scope", None)  # absent when the handshake was refused
        if scope is not None and not self.config.ws_per_message_deflate:
            scope["extensions"][EXTENSION] = self.write_frames

    def write_frames(self, data: bytes) -> bool:
        """Write ``data`` (whole text frames, :func:`text_frame`) to the client now.

        Only while the connection is open (accepted, no close sent or received) and its
        transport is not paused by flow control (its buffer is under the high-water mark):
        otherwise nothing is written and the answer is False — the caller then sends through
        ASGI, which waits for the buffer to drain, so a slow client never makes the server
        buffer more than one write beyond the mark.
        """
        # ``disconnected`` is uvicorn 0.5x's flag; earlier releases (from 0.35, the first
        # with this protocol) only close the transport, which ``is_closing`` sees
        if (getattr(self, "disconnected", False) or self.close_sent or not self.handshake_complete
                or self.initial_response is not None or not self.writable.is_set()
                or self.conn.state is not State.OPEN or self.transport.is_closing()):
            return False
        self.transport.write(data)
        return True


__all__ = ["EXTENSION", "FramedWebSocketProtocol", "text_frame"]
