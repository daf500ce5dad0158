"""Square SIDE DEPTH: mills a square outline from the current position.

A ger wizard in Python, built by `ger wizard build` with componentize-py.
Edit `expand` to make it yours; `ger run` rebuilds it when this changes.
`ger_wizard` (ger's Python SDK, put beside it when it is built) checks the
arguments, builds the blocks and exports the world `ger:wizard/wizard`
(wit/wizard.wit) as the `WitWorld` componentize-py wants.
"""

from componentize_py_types import Err
from ger_wizard import Description, comment, export, g0, g1, in_absolute


class Square:
    def describe(self):
        return (
            Description("Square", "mills a square outline from the current position", "Square SIDE DEPTH")
            .param("SIDE", "side of the square along +X and +Y")
            .param("DEPTH", "depth below the current Z")
        )

    def expand(self, args, state):
        side = args.positive(0)  # errors name SIDE and show the usage
        depth = args.positive(1)
        if state.feed is None:
            raise Err("no feed rate is set: give an F before calling Square")
        x, y, z = state.x, state.y, state.z
        moves = [
            g1().z(z - depth).f(state.feed),
            g1().x(x + side),
            g1().y(y + side),
            g1().x(x),
            g1().y(y),
            g0().z(z),
        ]
        return [comment(f"Square {side:g} x {depth:g}")] + in_absolute(state, moves)


WitWorld = export(Square)
