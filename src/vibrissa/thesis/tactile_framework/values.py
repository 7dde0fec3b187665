"""What the thesis says of its tactile framework (2.5, figure 2.17; 7.2): statements, no numbers.

The thesis proposes the framework and fills in its parts (chapters 4-6) but never runs it as
one system: it gives no figure to compare with, only these claims and the future work of 7.2.
"""

from __future__ import annotations

#: The framework's claims (section) that the experiment puts to the test.
THESIS: dict[str, str] = {
    "shaft_is_corner": "in the box world a shaft contact is with a corner; the tip would flick "
    "past the object (2.5.1)",
    "reposition": "after a shaft contact the whiskers can be accurately repositioned so that "
    "the next contact is at the tip (2.5.1, fig 2.17)",
    "tip_for_what": "object identity (surface angle, texture) can only be determined from tip "
    "contacts (2.5.1)",
    "map": "the results of these discriminations can be used for subsequent map building "
    "(fig 2.17); texture added to the map is future work (7.2)",
    "one_robot": "the best methods implemented in a single system on a mobile robot (2.5.2, 7.2)",
}
