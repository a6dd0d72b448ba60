"""Program buffers: what holds the lines a coordinate system runs.

The rotary ring and BREQ (``rotary``), fixed programs (``programs``), a stored line
(``program``), ``PC`` / ``PE`` (``program_counter``), the special lookahead buffer
(``lookahead_buffer``), the host's line numbering (``line_numbers``) and move timing
and profiles shared by the move modes (``motion``).
"""
