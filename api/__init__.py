"""motionsim's service layer: REST + WebSocket resources and TCP protocol adapters.

Translates wire formats into calls on ``app/``; holds no simulation state of its own.
"""
