"""The card's own facts: parameter names and stored values, models, I/O, channels, errors.

Error wording (``basic_errors``), the parameter names a program knows and may write
(``parameters``), the controller generations (``models``), system parameters (``system``),
the digital / analogue I/O image (``io``), the output channels (``output``), what AXISSTATUS
knows and the stored drive parameters (``axis_status``), the set-up commands a start-up
program issues (``setup_commands``) and the encoder / step ratios (``scaling``). Imports
nothing else of sim/trio at module level.
"""
