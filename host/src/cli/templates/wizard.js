// Square SIDE DEPTH: mills a square outline from the current position.
//
// A ger wizard in JavaScript, built by `ger wizard build` (esbuild bundles it
// with `ger_wizard`, ger's JavaScript SDK, and jco's QuickJS backend makes
// the component). Edit `expand` to make it yours; `ger run` rebuilds it when
// this changes. `ger_wizard` checks the arguments, builds the blocks and
// exports the world `ger:wizard/wizard` (wit/wizard.wit); an error thrown in
// `expand` is the call's error.

import { Description, comment, exportWizard, g0, g1, inAbsolute, WizardError } from "ger_wizard";

const Square = {
  describe: () =>
    new Description("Square", "mills a square outline from the current position", "Square SIDE DEPTH")
      .param("SIDE", "side of the square along +X and +Y")
      .param("DEPTH", "depth below the current Z"),

  expand(args, state) {
    const side = args.positive(0); // errors name SIDE and show the usage
    const depth = args.positive(1);
    if (state.feed === undefined) throw new WizardError("no feed rate is set: give an F before calling Square");
    const { x, y, z } = state;
    const moves = [
      g1().z(z - depth).f(state.feed),
      g1().x(x + side),
      g1().y(y + side),
      g1().x(x),
      g1().y(y),
      g0().z(z),
    ];
    return [comment(`Square ${side} x ${depth}`), ...inAbsolute(state, moves)];
  },
};

export const { describe, expand } = exportWizard(Square);
