"""Slot LENGTH DEPTH [PASSES]: mills a straight slot along +X from the current position.

A ger wizard in Python, built by `ger wizard build slot` with componentize-py.
The class `WitWorld` implements the world `ger:wizard/wizard` (see wit/wizard.wit):
`describe` says what the wizard is, `expand` turns one call into statements.
"""

import math

from componentize_py_types import Err
from wit_world import WitWorld as Wizard
from wit_world.imports import host
from wit_world.imports.types import (
    Arg_Number,
    Description,
    Distance,
    Param,
    Statement_Comment,
    Statement_Words,
    Word,
)

USAGE = "Slot LENGTH DEPTH [PASSES]"
PARAMS = ["LENGTH", "DEPTH", "PASSES"]


def words(*pairs):
    """A block from (letter, value) pairs: words(("G", 1), ("X", 10))."""
    return Statement_Words([Word(letter, float(value)) for letter, value in pairs])


def number(args, i, default=None):
    """Argument i as a positive number, or `default` when it is left out."""
    what = f"{PARAMS[i]} (argument {i + 1})"
    if i >= len(args):
        if default is None:
            raise Err(f"{what} is missing (usage: {USAGE})")
        return default
    arg = args[i]
    if not isinstance(arg, Arg_Number):
        raise Err(f'{what} must be a number, not the text "{arg.value}"')
    if arg.value <= 0:
        raise Err(f"{what} must be greater than 0, not {arg.value:g}")
    return arg.value


class WitWorld(Wizard):
    def describe(self):
        return Description(
            name="Slot",
            summary="mills a straight slot along +X, as wide as the tool, in equal passes",
            usage=USAGE,
            params=[
                Param("LENGTH", "length of the slot's centre line along X", False),
                Param("DEPTH", "depth below the current Z", False),
                Param("PASSES", "number of depth passes (default 1)", True),
            ],
        )

    def expand(self, args, state):
        if len(args) > len(PARAMS):
            raise Err(f"Slot takes 2 to 3 arguments, not {len(args)} (usage: {USAGE})")
        length = number(args, 0)
        depth = number(args, 1)
        passes = number(args, 2, 1.0)
        if passes != math.floor(passes):
            raise Err(f"PASSES (argument 3) must be a whole number, not {passes:g}")
        if state.feed is None:
            raise Err("no feed rate is set: give an F before calling Slot")
        host.log(f"slot of {length:g} at line {state.line}")
        x, top = state.x, state.z
        out = [Statement_Comment(f"Slot {length:g} long, {depth:g} deep, {int(passes)} passes")]
        if state.distance == Distance.INCREMENTAL:
            out.append(words(("G", 90)))
        # Zigzag down: each pass goes the other way along the slot.
        for n in range(1, int(passes) + 1):
            z = top - depth * n / passes
            out.append(words(("G", 1), ("Z", z), ("F", state.feed)))
            out.append(words(("G", 1), ("X", x + length if n % 2 == 1 else x)))
        out.append(words(("G", 0), ("Z", top)))
        out.append(words(("G", 0), ("X", x)))
        if state.distance == Distance.INCREMENTAL:
            out.append(words(("G", 91)))
        return out
