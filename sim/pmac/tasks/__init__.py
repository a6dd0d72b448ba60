"""The card's tasks and the processor time they share.

Servo and RTI instants (``scheduler``), the CPU model of servo / RTI / background
(``cpu``), the watchdog (``watchdog``) and the PLC programs run in those tasks (``plc``).
"""
