"""Write a ger wizard in Python: the Rust SDK's helpers, for componentize-py.

`ger wizard build` puts this module beside every Python wizard it builds, so
`app.py` may use it as it is::

    from ger_wizard import Description, export, g1

    class Square:
        def describe(self):
            return Description("Square", "mills a square", "Square SIDE").param("SIDE", "side length")

        def expand(self, args, state):
            side = args.positive(0)  # errors name SIDE and show the usage
            x, y = state.x, state.y
            return [g1().x(x + side), g1().y(y + side), g1().x(x), g1().y(y)]

    WitWorld = export(Square)

Argument errors read as the Rust SDK's do; blocks are built as there (`g0
g1 g2 g3 g(n) m(n)` then `.x .y .z .i .j .k .r .f .s .p .l .xy`); `ramp`
and `helix` take a cutter into material no steeper than an angle instead of
plunging it; `log`, `warn`, `find_tool`, `tools`, `stock` and
`machine_units` are the host's (wit/wizard.wit, ger:wizard@0.2.0). A test
checks this module against the WIT, so the two cannot drift apart.
"""

import math

from componentize_py_types import Err
from wit_world import WitWorld as _World
from wit_world.imports import host as _host
from wit_world.imports import types as _types

DEFAULT_ENTRY_ANGLE = 3.0
"""How steep an entry goes, in degrees from the horizontal, by default."""


class Description:
    """What a wizard says about itself; parameters in call order."""

    def __init__(self, name, summary, usage):
        self.name, self.summary, self.usage, self.params = name, summary, usage, []

    def param(self, name, description):
        """A required parameter."""
        self.params.append(_types.Param(name, description, False))
        return self

    def optional(self, name, description):
        """An optional parameter; optional ones come after the required ones."""
        self.params.append(_types.Param(name, description, True))
        return self

    def _wit(self):
        return _types.Description(self.name, self.summary, self.usage, list(self.params))


class Args:
    """A call's arguments, each named after the description's parameters."""

    def __init__(self, args, description):
        self._args, self._description = list(args), description

    def __len__(self):
        return len(self._args)

    def _what(self, i):
        params = self._description.params
        return f"{params[i].name} (argument {i + 1})" if i < len(params) else f"argument {i + 1}"

    def check_count(self):
        """Fails unless the count fits the description."""
        params = self._description.params
        required = sum(1 for p in params if not p.optional)
        if not required <= len(self._args) <= len(params):
            if required == len(params):
                expected = f"{required} argument{'' if required == 1 else 's'}"
            else:
                expected = f"{required} to {len(params)} arguments"
            raise Err(
                f"{self._description.name} takes {expected}, not {len(self._args)} "
                f"(usage: {self._description.usage})"
            )

    def optional_number(self, i):
        """A number that may be left out (None)."""
        if i >= len(self._args):
            return None
        arg = self._args[i]
        if not isinstance(arg, _types.Arg_Number):
            raise Err(f'{self._what(i)} must be a number, not the text "{arg.value}"')
        return arg.value

    def number(self, i):
        """A number that must be there."""
        value = self.optional_number(i)
        if value is None:
            raise Err(f"{self._what(i)} is missing (usage: {self._description.usage})")
        return value

    def optional_positive(self, i):
        """A number greater than zero, if given."""
        value = self.optional_number(i)
        if value is not None and not value > 0:
            raise Err(f"{self._what(i)} must be greater than 0, not {value:g}")
        return value

    def positive(self, i):
        """A number greater than zero."""
        self.number(i)
        return self.optional_positive(i)

    def optional_non_negative(self, i):
        """A number of zero or more, if given: a radius or an allowance."""
        value = self.optional_number(i)
        if value is not None and value < 0:
            raise Err(f"{self._what(i)} must not be negative, not {value:g}")
        return value

    def whole(self, i, least):
        """A whole number of at least `least`, e.g. a count of holes."""
        value = self.number(i)
        if value != math.floor(value) or value < least:
            raise Err(f"{self._what(i)} must be a whole number of at least {least}, not {value:g}")
        return int(value)

    def choice(self, i, choices):
        """Which of `choices` argument i names, as its index; the first when it is left out."""
        if i >= len(self._args):
            return 0
        given = self.text(i)
        if given in choices:
            return choices.index(given)
        quoted = [f'"{c}"' for c in choices]
        listed = quoted[-1] if len(quoted) == 1 else f"{', '.join(quoted[:-1])} or {quoted[-1]}"
        raise Err(f'{self._what(i)} is {listed}, not "{given}"')

    def text(self, i):
        """A text argument (written in double quotes)."""
        if i >= len(self._args):
            raise Err(f"{self._what(i)} is missing (usage: {self._description.usage})")
        arg = self._args[i]
        if not isinstance(arg, _types.Arg_Text):
            raise Err(f"{self._what(i)} must be a text in double quotes, not the number {arg.value:g}")
        return arg.value


class Block:
    """One block of words: `g1().x(10).f(300)`."""

    def __init__(self, letter, number):
        self.words = [(letter, float(number))]

    def _word(self, letter, value):
        self.words.append((letter, float(value)))
        return self

    def xy(self, x, y):
        return self._word("X", x)._word("Y", y)


for _letter in "XYZIJKRFSPL":
    setattr(Block, _letter.lower(), lambda self, value, _l=_letter: self._word(_l, value))


def g(number):
    return Block("G", number)


def g0():
    return g(0)


def g1():
    return g(1)


def g2():
    return g(2)


def g3():
    return g(3)


def m(number):
    return Block("M", number)


def comment(text):
    return _types.Statement_Comment(text)


def text(gcode):
    """G-code text that ger parses as if it stood at the call."""
    return _types.Statement_Text(gcode)


def call(name, *args):
    """A call of another wizard: numbers and texts."""
    wit = [_types.Arg_Text(a) if isinstance(a, str) else _types.Arg_Number(float(a)) for a in args]
    return _types.Statement_Call(_types.WizardCall(name, wit))


def _statement(item):
    if isinstance(item, Block):
        return _types.Statement_Words([_types.Word(letter, value) for letter, value in item.words])
    return item


def in_absolute(state, moves):
    """`moves` written in absolute coordinates, between G90 and G91 when the call was in G91."""
    if state.distance == _types.Distance.ABSOLUTE:
        return moves
    return [g(90)] + list(moves) + [g(91)]


def require_cutter(state, job):
    """The loaded tool, which must be in the table and cut sideways: `job` says what needs it."""
    tool = state.tool
    if tool is None:
        raise Err(f"tool T{state.tool_number} is not in the tool table, so its diameter is unknown")
    if tool.kind in (_types.ToolKind.DRILL, _types.ToolKind.CENTER_DRILL):
        raise Err(f"T{tool.number} is a drill; {job}")
    return tool


def _slope(angle):
    if not 0 < angle < 90:
        raise Err(f"an entry angle must be above 0 and below 90 degrees, not {angle:g}")
    return math.tan(math.radians(angle))


def _equal_passes(start, end, most):
    count = max(1, math.ceil((start - end) / most))
    return [end if n == count else start - (start - end) * n / count for n in range(1, count + 1)]


def levels(top, depth, stepdown):
    """The levels a cut goes down to from `top`: `stepdown` apart, the last exactly at `depth` below it."""
    count = max(1, math.ceil(depth / stepdown))
    return [top - depth if n == count else top - n * stepdown for n in range(1, count + 1)]


def ramp(a, b, from_z, to_z, angle, feed):
    """Down from `a` at `from_z` to `to_z`, back and forth along a-b no steeper than `angle`; ends level at `a`."""
    length = math.hypot(b[0] - a[0], b[1] - a[1])
    slope = _slope(angle)
    if not length > 0:
        raise Err("a ramp needs a line of some length to run along")
    if from_z < to_z:
        raise Err(f"a ramp goes down: Z{to_z:g} is above Z{from_z:g}")
    out, at_a = [], True
    for n, z in enumerate(_equal_passes(from_z, to_z, length * slope)):
        x, y = b if at_a else a
        block = g1().xy(x, y).z(z)
        out.append(block.f(feed) if n == 0 else block)
        at_a = not at_a
    if at_a:
        out.append(g1().xy(*b))
    out.append(g1().xy(*a))
    return out


def helix(centre, start, from_z, to_z, angle, clockwise, feed):
    """Down from `start` at `from_z` to `to_z` round `centre` in whole turns no steeper than `angle`, then a level one."""
    slope = _slope(angle)
    i, j = centre[0] - start[0], centre[1] - start[1]
    radius = math.hypot(i, j)
    if not radius > 0:
        raise Err("a helix needs a radius: its start is on its centre")
    if from_z < to_z:
        raise Err(f"a helix goes down: Z{to_z:g} is above Z{from_z:g}")
    arc = g2 if clockwise else g3
    out = []
    for n, z in enumerate(_equal_passes(from_z, to_z, 2 * math.pi * radius * slope)):
        block = arc().xy(*start).z(z).i(i).j(j)
        out.append(block.f(feed) if n == 0 else block)
    out.append(arc().xy(*start).i(i).j(j))
    return out


def log(message):
    """A line shown with the diagnostic if the call fails."""
    _host.log(message)


def warn(message):
    """A warning at the call (`ger check --deny warnings` fails on it); the statements still run."""
    _host.warn(message)


def find_tool(number):
    """A tool of the machine's table, in the program's units, or None."""
    return _host.find_tool(number)


def tools():
    """The whole tool table, in the program's units, by number."""
    return _host.tools()


def stock():
    """The stock block (min_x ... max_z in the program's coordinates), or None."""
    return _host.stock()


def machine_units():
    """The machine's unit (types.Units), whatever G20/G21 the program is in."""
    return _host.machine_units()


def export(wizard):
    """The `WitWorld` componentize-py wants, from a class with `describe()`
    (a `Description`) and `expand(args, state)` (`Args`, the machine state;
    it returns blocks and statements, or raises `Err`)."""

    class Exported(_World):
        def describe(self):
            return wizard().describe()._wit()

        def expand(self, args, state):
            instance = wizard()
            checked = Args(args, instance.describe())
            checked.check_count()
            return [_statement(item) for item in instance.expand(checked, state)]

    return Exported
