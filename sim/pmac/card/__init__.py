"""The card: its variables, memory and non-volatile state.

I/P/Q/M variables (``variables``) and the I-variable rules (``ivar_ranges``), factory
defaults (``factory``), M-variable definitions (``mvar_defs``) and values in card memory
(``mvars``), the address map of simulated registers (``registers``), the host's memory
reads and writes (``memory_commands``), ``SAVE`` / ``$$$`` (``card_commands``) and the
meaning of every ``ERRnnn`` (``error_codes``).
"""
