// Circle RADIUS DEPTH: mills a circular groove centred on the current position.
//
// A ger wizard in JavaScript on ger's JavaScript SDK (`ger_wizard`), built by
// `ger wizard build circle`: esbuild bundles the two, jco's QuickJS backend
// makes the component. The SDK checks the arguments against the description
// (errors name the parameter and show the usage), builds the blocks, and
// brings the cutter down by a helix along the groove instead of a plunge.

import { Description, comment, exportWizard, g0, helix, inAbsolute, log, requireCutter } from "ger_wizard";
import { DEFAULT_ENTRY_ANGLE, WizardError } from "ger_wizard";

const Circle = {
  describe: () =>
    new Description("Circle", "mills a circular groove of the given radius around the current position", "Circle RADIUS DEPTH")
      .param("RADIUS", "radius of the tool's centre path")
      .param("DEPTH", "depth below the current Z"),

  expand(args, state) {
    const radius = args.positive(0);
    const depth = args.positive(1);
    requireCutter(state, "a groove needs an end mill");
    if (state.feed === undefined) throw new WizardError("no feed rate is set: give an F before calling Circle");
    if (state.plane !== "xy") throw new WizardError("Circle cuts in the XY plane: call it under G17");
    log(`circle of radius ${radius} at line ${state.line}`);
    const { x, y, z } = state;
    // Down round the groove itself, counter-clockwise, then a level lap.
    const start = [x + radius, y];
    const moves = [
      g0().xy(...start),
      ...helix([x, y], start, z, z - depth, DEFAULT_ENTRY_ANGLE, false, state.feed),
      g0().z(z),
      g0().xy(x, y),
    ];
    return [comment(`Circle radius ${radius}, ${depth} deep`), ...inAbsolute(state, moves)];
  },
};

export const { describe, expand } = exportWizard(Circle);
