"""The bare FastAPI reference: the REST rotary-lines shapes (pydantic request, JSON response)
on uvicorn with the same server settings as ``motionsim serve``, and no simulation behind
them. Prints ``listening http://127.0.0.1:PORT`` once it accepts connections."""

from __future__ import annotations

import socket

import uvicorn
from fastapi import FastAPI
from pydantic import BaseModel

app = FastAPI()
_store: list[str] = []


class Lines(BaseModel):
    lines: list[str]
    first_seq: int | None = None


@app.post("/controllers/{cid}/coord/{cs}/rotary/lines")
async def lines(cid: str, cs: int, body: Lines) -> dict:
    _store.extend(body.lines)
    del _store[:-1000]
    return {"accepted": len(body.lines), "stored": len(body.lines), "lines_ahead": len(_store),
            "free_words": 1000, "breq": True}


def main() -> None:
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.bind(("127.0.0.1", 0))
    port = sock.getsockname()[1]
    config = uvicorn.Config(app, log_level="warning", access_log=False)
    server = uvicorn.Server(config)
    print(f"listening http://127.0.0.1:{port}", flush=True)
    server.run(sockets=[sock])


if __name__ == "__main__":
    main()
