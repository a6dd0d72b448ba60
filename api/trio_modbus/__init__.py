"""Trio Modbus TCP slave (port 502): holding registers = VR(); sans-I/O codec + asyncio server."""
