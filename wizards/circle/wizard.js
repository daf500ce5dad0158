// Circle RADIUS DEPTH: mills a circular groove centred on the current position.
//
// A ger wizard in JavaScript, built by `ger wizard build circle` with jco
// (QuickJS backend). The module exports the world `ger:wizard/wizard`'s
// functions (see wit/wizard.wit): `describe` and `expand`. Variants are
// `{ tag, val }` objects, records are objects with camelCase fields, options
// are a value or `undefined`, and a thrown string is the call's error.
import { log } from "ger:wizard/host@0.2.0";

const USAGE = "Circle RADIUS DEPTH";
const PARAMS = ["RADIUS", "DEPTH"];

function word(letter, value) {
  return { letter, value };
}

function block(...words) {
  return { tag: "words", val: words };
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
    name: "Circle",
    summary: "mills a circular groove of the given radius around the current position",
    usage: USAGE,
    params: [
      { name: "RADIUS", description: "radius of the tool's centre path", optional: false },
      { name: "DEPTH", description: "depth below the current Z", optional: false },
    ],
  };
}

export function expand(args, state) {
  if (args.length !== PARAMS.length) throw `Circle takes 2 arguments, not ${args.length} (usage: ${USAGE})`;
  const radius = positive(args, 0);
  const depth = positive(args, 1);
  if (state.feed === undefined) throw "no feed rate is set: give an F before calling Circle";
  if (state.plane !== "xy") throw "Circle cuts in the XY plane: call it under G17";
  log(`circle of radius ${radius} at line ${state.line}`);
  const { x, y, z } = state;
  const out = [{ tag: "comment", val: `Circle radius ${radius}, ${depth} deep` }];
  if (state.distance === "incremental") out.push(block(word("G", 90)));
  out.push(block(word("G", 0), word("X", x + radius), word("Y", y)));
  out.push(block(word("G", 1), word("Z", z - depth), word("F", state.feed)));
  // A full circle counter-clockwise: the centre is at I = -RADIUS from the start.
  out.push(block(word("G", 3), word("X", x + radius), word("Y", y), word("I", -radius), word("J", 0)));
  out.push(block(word("G", 0), word("Z", z)));
  out.push(block(word("G", 0), word("X", x), word("Y", y)));
  if (state.distance === "incremental") out.push(block(word("G", 91)));
  return out;
}
