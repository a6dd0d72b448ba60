"""Trio command line over TCP: sans-I/O codec in protocol.py, asyncio server in server.py."""
