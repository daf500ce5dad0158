"""Square SIDE DEPTH: mills a square outline from the current position.

A ger wizard in Python, built by `ger wizard build` with componentize-py.
Edit `expand` to make it yours; `ger run` rebuilds it when this changes.
The class `WitWorld` implements the world `ger:wizard/wizard` (wit/wizard.wit).
"""

from componentize_py_types import Err
from wit_world import WitWorld as Wizard
from wit_world.imports.types import (
    Arg_Number,
    Description,
    Distance,
    Param,
    Statement_Comment,
    Statement_Words,
    Word,
)

USAGE = "Square SIDE DEPTH"
PARAMS = ["SIDE", "DEPTH"]


def words(*pairs):
    """A block from (letter, value) pairs: words(("G", 1), ("X", 10))."""
    return Statement_Words([Word(letter, float(value)) for letter, value in pairs])


def positive(args, i):
    """Argument i, which must be a number above zero."""
    what = f"{PARAMS[i]} (argument {i + 1})"
    if i >= len(args):
        raise Err(f"{what} is missing (usage: {USAGE})")
    arg = args[i]
    if not isinstance(arg, Arg_Number):
        raise Err(f'{what} must be a number, not the text "{arg.value}"')
    if arg.value <= 0:
        raise Err(f"{what} must be greater than 0, not {arg.value:g}")
    return arg.value


class WitWorld(Wizard):
    def describe(self):
        return Description(
            name="Square",
            summary="mills a square outline from the current position",
            usage=USAGE,
            params=[
                Param("SIDE", "side of the square along +X and +Y", False),
                Param("DEPTH", "depth below the current Z", False),
            ],
        )

    def expand(self, args, state):
        if len(args) > len(PARAMS):
            raise Err(f"Square takes {len(PARAMS)} arguments, not {len(args)} (usage: {USAGE})")
        side = positive(args, 0)
        depth = positive(args, 1)
        if state.feed is None:
            raise Err("no feed rate is set: give an F before calling Square")
        x, y, z = state.x, state.y, state.z
        out = [Statement_Comment(f"Square {side:g} x {depth:g}")]
        if state.distance == Distance.INCREMENTAL:
            out.append(words(("G", 90)))
        out.append(words(("G", 1), ("Z", z - depth), ("F", state.feed)))
        out.append(words(("G", 1), ("X", x + side)))
        out.append(words(("G", 1), ("Y", y + side)))
        out.append(words(("G", 1), ("X", x)))
        out.append(words(("G", 1), ("Y", y)))
        out.append(words(("G", 0), ("Z", z)))
        if state.distance == Distance.INCREMENTAL:
            out.append(words(("G", 91)))
        return out
