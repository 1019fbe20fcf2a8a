"""Contact-element states, shared by the law, the integrators and the signals.

Codes as stored in the records: 0 separate (no contact force), 1 stick
(friction below mu N, slider fixed), 2 slip (|F| = mu N, slider dragged).
"""

SEPARATE, STICK, SLIP = 0, 1, 2
STATE_NAMES = ("separate", "stick", "slip")
