"""PMAC Ethernet protocol (TCP 1025): sans-I/O codec (protocol.py), asyncio server (server.py)."""
