// Write a ger wizard in JavaScript: the Rust SDK's helpers, for jco.
//
// `ger wizard build` bundles this module with every JavaScript wizard it
// builds (esbuild, then jco's QuickJS backend), so `wizard.js` may use it as
// it is:
//
//     import { Description, exportWizard, g1 } from "ger_wizard";
//
//     const Square = {
//       describe: () => new Description("Square", "mills a square", "Square SIDE").param("SIDE", "side length"),
//       expand(args, state) {
//         const side = args.positive(0); // errors name SIDE and show the usage
//         const { x, y } = state;
//         return [g1().x(x + side), g1().y(y + side), g1().x(x), g1().y(y)];
//       },
//     };
//
//     export const { describe, expand } = exportWizard(Square);
//
// Argument errors read as the Rust SDK's do (an `Error` thrown with one is
// the call's error); blocks are built as there (`g0 g1 g2 g3 g(n) m(n)` then
// `.x .y .z .i .j .k .r .f .s .p .l .xy`); `ramp` and `helix` take a cutter
// into material no steeper than an angle instead of plunging it; `log`,
// `warn`, `findTool`, `tools`, `stock` and `machineUnits` are the host's
// (wit/wizard.wit, ger:wizard@0.2.0). A test checks this module against the
// WIT, so the two cannot drift apart.

import * as host from "ger:wizard/host@0.2.0";

/** How steep an entry goes, in degrees from the horizontal, by default. */
export const DEFAULT_ENTRY_ANGLE = 3.0;

/** An error a wizard throws to refuse a call: ger shows its message at the call. */
export class WizardError extends Error {}

function fail(message) {
  throw new WizardError(message);
}

/** What a wizard says about itself; parameters in call order. */
export class Description {
  constructor(name, summary, usage) {
    Object.assign(this, { name, summary, usage, params: [] });
  }

  /** A required parameter. */
  param(name, description) {
    this.params.push({ name, description, optional: false });
    return this;
  }

  /** An optional parameter; optional ones come after the required ones. */
  optional(name, description) {
    this.params.push({ name, description, optional: true });
    return this;
  }
}

/** A call's arguments, each named after the description's parameters. */
export class Args {
  constructor(args, description) {
    this.args = args;
    this.description = description;
  }

  get length() {
    return this.args.length;
  }

  what(i) {
    const params = this.description.params;
    return i < params.length ? `${params[i].name} (argument ${i + 1})` : `argument ${i + 1}`;
  }

  /** Fails unless the count fits the description. */
  checkCount() {
    const { params, name, usage } = this.description;
    const required = params.filter((p) => !p.optional).length;
    const count = this.args.length;
    if (count < required || count > params.length) {
      const expected =
        required === params.length
          ? `${required} argument${required === 1 ? "" : "s"}`
          : `${required} to ${params.length} arguments`;
      fail(`${name} takes ${expected}, not ${count} (usage: ${usage})`);
    }
  }

  /** A number that may be left out (undefined). */
  optionalNumber(i) {
    const arg = this.args[i];
    if (arg === undefined) return undefined;
    if (arg.tag !== "number") fail(`${this.what(i)} must be a number, not the text "${arg.val}"`);
    return arg.val;
  }

  /** A number that must be there. */
  number(i) {
    const value = this.optionalNumber(i);
    if (value === undefined) fail(`${this.what(i)} is missing (usage: ${this.description.usage})`);
    return value;
  }

  /** A number greater than zero, if given. */
  optionalPositive(i) {
    const value = this.optionalNumber(i);
    if (value !== undefined && !(value > 0)) fail(`${this.what(i)} must be greater than 0, not ${value}`);
    return value;
  }

  /** A number greater than zero. */
  positive(i) {
    this.number(i);
    return this.optionalPositive(i);
  }

  /** A number of zero or more, if given: a radius or an allowance. */
  optionalNonNegative(i) {
    const value = this.optionalNumber(i);
    if (value !== undefined && value < 0) fail(`${this.what(i)} must not be negative, not ${value}`);
    return value;
  }

  /** A whole number of at least `least`, e.g. a count of holes. */
  whole(i, least) {
    const value = this.number(i);
    if (!Number.isInteger(value) || value < least) {
      fail(`${this.what(i)} must be a whole number of at least ${least}, not ${value}`);
    }
    return value;
  }

  /** Which of `choices` argument i names, as its index; the first when it is left out. */
  choice(i, choices) {
    if (i >= this.args.length) return 0;
    const given = this.text(i);
    const index = choices.indexOf(given);
    if (index >= 0) return index;
    const quoted = choices.map((c) => `"${c}"`);
    const listed = quoted.length === 1 ? quoted[0] : `${quoted.slice(0, -1).join(", ")} or ${quoted.at(-1)}`;
    return fail(`${this.what(i)} is ${listed}, not "${given}"`);
  }

  /** A text argument (written in double quotes). */
  text(i) {
    const arg = this.args[i];
    if (arg === undefined) fail(`${this.what(i)} is missing (usage: ${this.description.usage})`);
    if (arg.tag !== "text") fail(`${this.what(i)} must be a text in double quotes, not the number ${arg.val}`);
    return arg.val;
  }
}

/** One block of words: `g1().x(10).f(300)`. */
export class Block {
  constructor(letter, number) {
    this.words = [[letter, number]];
  }

  word(letter, value) {
    this.words.push([letter.toUpperCase(), value]);
    return this;
  }

  xy(x, y) {
    return this.word("X", x).word("Y", y);
  }
}

for (const letter of "XYZIJKRFSPL") {
  Block.prototype[letter.toLowerCase()] = function (value) {
    return this.word(letter, value);
  };
}

export const g = (number) => new Block("G", number);
export const g0 = () => g(0);
export const g1 = () => g(1);
export const g2 = () => g(2);
export const g3 = () => g(3);
export const m = (number) => new Block("M", number);

export const comment = (text) => ({ tag: "comment", val: text });

/** G-code text that ger parses as if it stood at the call. */
export const text = (gcode) => ({ tag: "text", val: gcode });

/** A call of another wizard: numbers and texts. */
export function call(name, ...args) {
  const wit = args.map((a) => (typeof a === "string" ? { tag: "text", val: a } : { tag: "number", val: a }));
  return { tag: "call", val: { name, args: wit } };
}

function statement(item) {
  if (item instanceof Block) {
    return { tag: "words", val: item.words.map(([letter, value]) => ({ letter, value })) };
  }
  return item;
}

/** `moves` written in absolute coordinates, between G90 and G91 when the call was in G91. */
export function inAbsolute(state, moves) {
  return state.distance === "absolute" ? moves : [g(90), ...moves, g(91)];
}

/** The loaded tool, which must be in the table and cut sideways: `job` says what needs it. */
export function requireCutter(state, job) {
  const tool = state.tool;
  if (tool === undefined) fail(`tool T${state.toolNumber} is not in the tool table, so its diameter is unknown`);
  if (tool.kind === "drill" || tool.kind === "center-drill") fail(`T${tool.number} is a drill; ${job}`);
  return tool;
}

function slope(angle) {
  if (!(angle > 0 && angle < 90)) fail(`an entry angle must be above 0 and below 90 degrees, not ${angle}`);
  return Math.tan((angle * Math.PI) / 180);
}

function equalPasses(start, end, most) {
  const count = Math.max(1, Math.ceil((start - end) / most));
  return Array.from({ length: count }, (_, k) => (k + 1 === count ? end : start - ((start - end) * (k + 1)) / count));
}

/** The levels a cut goes down to from `top`: `stepdown` apart, the last exactly at `depth` below it. */
export function levels(top, depth, stepdown) {
  const count = Math.max(1, Math.ceil(depth / stepdown));
  return Array.from({ length: count }, (_, k) => (k + 1 === count ? top - depth : top - (k + 1) * stepdown));
}

/** Down from `a` at `fromZ` to `toZ`, back and forth along a-b no steeper than `angle`; ends level at `a`. */
export function ramp(a, b, fromZ, toZ, angle, feed) {
  const length = Math.hypot(b[0] - a[0], b[1] - a[1]);
  const rise = slope(angle);
  if (!(length > 0)) fail("a ramp needs a line of some length to run along");
  if (fromZ < toZ) fail(`a ramp goes down: Z${toZ} is above Z${fromZ}`);
  const out = [];
  let atA = true;
  equalPasses(fromZ, toZ, length * rise).forEach((z, n) => {
    const [x, y] = atA ? b : a;
    const block = g1().xy(x, y).z(z);
    out.push(n === 0 ? block.f(feed) : block);
    atA = !atA;
  });
  if (atA) out.push(g1().xy(...b));
  out.push(g1().xy(...a));
  return out;
}

/** Down from `start` at `fromZ` to `toZ` round `centre` in whole turns no steeper than `angle`, then a level one. */
export function helix(centre, start, fromZ, toZ, angle, clockwise, feed) {
  const rise = slope(angle);
  const [i, j] = [centre[0] - start[0], centre[1] - start[1]];
  const radius = Math.hypot(i, j);
  if (!(radius > 0)) fail("a helix needs a radius: its start is on its centre");
  if (fromZ < toZ) fail(`a helix goes down: Z${toZ} is above Z${fromZ}`);
  const arc = clockwise ? g2 : g3;
  const out = equalPasses(fromZ, toZ, 2 * Math.PI * radius * rise).map((z, n) => {
    const block = arc().xy(...start).z(z).i(i).j(j);
    return n === 0 ? block.f(feed) : block;
  });
  out.push(arc().xy(...start).i(i).j(j));
  return out;
}

/** A line shown with the diagnostic if the call fails. */
export const log = (message) => host.log(message);

/** A warning at the call (`ger check --deny warnings` fails on it); the statements still run. */
export const warn = (message) => host.warn(message);

/** A tool of the machine's table, in the program's units, or undefined. */
export const findTool = (number) => host.findTool(number);

/** The whole tool table, in the program's units, by number. */
export const tools = () => host.tools();

/** The stock block (minX ... maxZ in the program's coordinates), or undefined. */
export const stock = () => host.stock();

/** The machine's unit ("mm" or "inch"), whatever G20/G21 the program is in. */
export const machineUnits = () => host.machineUnits();

/**
 * The `describe` and `expand` the component exports, from an object with
 * `describe()` (a `Description`) and `expand(args, state)` (`Args`, the
 * machine state; it returns blocks and statements, or throws).
 */
export function exportWizard(wizard) {
  return {
    describe() {
      const { name, summary, usage, params } = wizard.describe();
      return { name, summary, usage, params };
    },
    expand(args, state) {
      try {
        const checked = new Args(args, wizard.describe());
        checked.checkCount();
        return wizard.expand(checked, state).map(statement);
      } catch (error) {
        // jco makes a thrown string the call's error.
        throw error instanceof Error ? error.message : String(error);
      }
    },
  };
}
