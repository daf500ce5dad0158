// Square SIDE DEPTH: mills a square outline from the current position.
//
// A ger wizard in JavaScript, built by `ger wizard build` with jco (QuickJS
// backend). Edit `expand` to make it yours; `ger run` rebuilds it when this
// changes. The module exports the world `ger:wizard/wizard`'s functions (see
// wit/wizard.wit). Variants are `{ tag, val }` objects, records are objects
// with camelCase fields, options are a value or `undefined`, and a thrown
// string is the call's error.

const USAGE = "Square SIDE DEPTH";
const PARAMS = ["SIDE", "DEPTH"];

function block(...pairs) {
  return { tag: "words", val: pairs.map(([letter, value]) => ({ letter, value })) };
}

function positive(args, i) {
  const what = `${PARAMS[i]} (argument ${i + 1})`;
  const arg = args[i];
  if (arg === undefined) throw `${what} is missing (usage: ${USAGE})`;
  if (arg.tag !== "number") throw `${what} must be a number, not the text "${arg.val}"`;
  if (!(arg.val > 0)) throw `${what} must be greater than 0, not ${arg.val}`;
  return arg.val;
}

export function describe() {
  return {
    name: "Square",
    summary: "mills a square outline from the current position",
    usage: USAGE,
    params: [
      { name: "SIDE", description: "side of the square along +X and +Y", optional: false },
      { name: "DEPTH", description: "depth below the current Z", optional: false },
    ],
  };
}

export function expand(args, state) {
  if (args.length > PARAMS.length) throw `Square takes ${PARAMS.length} arguments, not ${args.length} (usage: ${USAGE})`;
  const side = positive(args, 0);
  const depth = positive(args, 1);
  if (state.feed === undefined) throw "no feed rate is set: give an F before calling Square";
  const { x, y, z } = state;
  const out = [{ tag: "comment", val: `Square ${side} x ${depth}` }];
  if (state.distance === "incremental") out.push(block(["G", 90]));
  out.push(block(["G", 1], ["Z", z - depth], ["F", state.feed]));
  out.push(block(["G", 1], ["X", x + side]));
  out.push(block(["G", 1], ["Y", y + side]));
  out.push(block(["G", 1], ["X", x]));
  out.push(block(["G", 1], ["Y", y]));
  out.push(block(["G", 0], ["Z", z]));
  if (state.distance === "incremental") out.push(block(["G", 91]));
  return out;
}
