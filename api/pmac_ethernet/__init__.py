"""PMAC Ethernet protocol (port 1025): sans-I/O codec in protocol.py, asyncio server in server.py."""
