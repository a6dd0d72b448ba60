"""The host terminal: one port's command line and what it answers.

On-line dispatch (``terminal``), control characters (``control_chars``), ``LIST``
(``list_commands``, formatted by ``listing``) and the valid-but-not-simulated table
(``not_simulated``).
"""
