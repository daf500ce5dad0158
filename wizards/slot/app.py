"""Slot LENGTH DEPTH [PASSES]: mills a straight slot along +X from the current position.

A ger wizard in Python, built by `ger wizard build slot` with componentize-py,
on ger's Python SDK (`ger_wizard`, put beside it when it is built): `describe`
says what the wizard is, `expand` turns one call into statements.
"""

from componentize_py_types import Err
from ger_wizard import Description, comment, export, g0, g1, in_absolute, log


class Slot:
    def describe(self):
        return (
            Description(
                "Slot",
                "mills a straight slot along +X, as wide as the tool, in equal passes",
                "Slot LENGTH DEPTH [PASSES]",
            )
            .param("LENGTH", "length of the slot's centre line along X")
            .param("DEPTH", "depth below the current Z")
            .optional("PASSES", "number of depth passes (default 1)")
        )

    def expand(self, args, state):
        length = args.positive(0)
        depth = args.positive(1)
        passes = args.whole(2, 1) if len(args) > 2 else 1
        if state.feed is None:
            raise Err("no feed rate is set: give an F before calling Slot")
        log(f"slot of {length:g} at line {state.line}")
        x, top = state.x, state.z
        moves = []
        # Zigzag down: each pass goes the other way along the slot.
        for n in range(1, passes + 1):
            moves.append(g1().z(top - depth * n / passes).f(state.feed))
            moves.append(g1().x(x + length if n % 2 == 1 else x))
        moves += [g0().z(top), g0().x(x)]
        return [comment(f"Slot {length:g} long, {depth:g} deep, {passes} passes")] + in_absolute(state, moves)


WitWorld = export(Slot)
