"""Motors: servo-loop state, jog and home moves, and the motor status words.

``motors`` owns each motor's loop state and displacement, ``jog`` is the jog / home
trajectory alone, ``motor_status`` builds the ``#n?`` reply.
"""
