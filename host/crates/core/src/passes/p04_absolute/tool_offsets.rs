//! The tool table entries the program writes (G10 L1, L10, L11) and the
//! tool offsets G43/G44 apply from them: what G10 L10 and L11 need to set
//! an entry from where the machine is. An entry the program has not
//! written is the controller's, unknown to ger, as is an offset applied
//! from one.
//!
//! ger follows the tool's tip in program terms (the controller adds the
//! offset to every move), so the machine's controlled point is the tip plus
//! the offset in force at the last move: G43 and G49 change what the
//! position reads, not where the machine is, until the next move.

use std::collections::HashMap;

use crate::diag::{Diagnostic, Span};
use crate::geom::turn;
use crate::statement::{Axes, Frame, Value};

pub struct ToolOffsets {
    /// Entries as the program wrote them, axis by axis (machine units).
    written: HashMap<u32, [Option<f64>; 3]>,
    /// The offset G43/G44 applied, axis by axis: zero until G43 and after G49.
    in_force: [Option<f64>; 3],
    /// The offset in force when the machine last moved.
    at_last_move: [Option<f64>; 3],
    /// The register G43/G44 applied, for messages.
    register: Option<u32>,
}

impl Default for ToolOffsets {
    fn default() -> ToolOffsets {
        ToolOffsets { written: HashMap::new(), in_force: [Some(0.0); 3], at_last_move: [Some(0.0); 3], register: None }
    }
}

impl ToolOffsets {
    /// G10 L1: the axes given; the others keep what the entry had.
    pub fn write(&mut self, tool: u32, offsets: [Option<f64>; 3]) {
        let entry = self.written.entry(tool).or_insert([None; 3]);
        for (kept, given) in entry.iter_mut().zip(offsets) {
            if given.is_some() {
                *kept = given;
            }
        }
    }

    /// G43 Hn (`positive`) or G44 Hn: entry n's offsets, added or taken away.
    pub fn apply(&mut self, register: u32, positive: bool) {
        let sign = if positive { 1.0 } else { -1.0 };
        let entry = self.written.get(&register).copied().unwrap_or([None; 3]);
        self.in_force = entry.map(|axis| axis.map(|v| sign * v));
        self.register = Some(register);
    }

    /// G49.
    pub fn cancel(&mut self) {
        self.in_force = [Some(0.0); 3];
        self.register = None;
    }

    /// The machine has moved, with the offset in force.
    pub fn moved(&mut self) {
        self.at_last_move = self.in_force;
    }

    /// G10 L10/L11: tool `tool`'s entry such that, applied, the tool (its
    /// tip now at `tip`) reads `given` in `frame`: the controlled point
    /// less the point `given` names there. An axis not given keeps its
    /// entry, unless the frame is turned and the other of X and Y is given:
    /// LinuxCNC then writes both, the one not given being where the tool
    /// reads with the entry as it is. The axes written are returned, for
    /// the G10 L1 that says them.
    pub fn entry_from(
        &mut self,
        tool: u32,
        tip: [f64; 3],
        given: Axes,
        frame: Frame,
        span: Span,
    ) -> Result<Axes, Diagnostic> {
        let Frame { origin, rotation } = frame;
        let turned = rotation.rem_euclid(360.0) != 0.0 && (given.x.is_some() || given.y.is_some());
        let written = [given.x.is_some() || turned, given.y.is_some() || turned, given.z.is_some()];
        let entry = self.written.get(&tool).copied().unwrap_or([None; 3]);
        let unknown = |what: String| {
            let message = format!("G10 sets tool {tool}'s entry from where the machine is, with {what}, which the controller's tool table holds: ger cannot say what it is");
            Err(Diagnostic::error(span, message)
                .with_help("write the entry first with G10 L1, or cancel the tool offset with G49"))
        };
        let mut controlled = [0.0; 3];
        for axis in (0..3).filter(|&axis| written[axis]) {
            let Some(offset) = self.at_last_move[axis] else {
                return unknown(format!("the offset of entry {} in force", self.register.unwrap_or(0)));
            };
            controlled[axis] = tip[axis] + offset;
        }
        // Only a turned frame reads an axis not given.
        let mut reading = [0.0; 2];
        if turned && (given.x.is_none() || given.y.is_none()) {
            let (Some(x), Some(y)) = (entry[0], entry[1]) else { return unknown("its own X and Y".to_string()) };
            reading = turn([controlled[0] - x - origin[0], controlled[1] - y - origin[1]], -rotation);
        }
        let wanted = [0, 1].map(|axis| given.get(axis).map_or(reading[axis], |v| v.value));
        let [x, y] = turn(wanted, rotation);
        let target = [x + origin[0], y + origin[1], given.z.map_or(0.0, |z| z.value) + origin[2]];
        let entry: [Option<f64>; 3] =
            std::array::from_fn(|axis| written[axis].then(|| controlled[axis] - target[axis]));
        self.write(tool, entry);
        let value =
            |axis: usize| entry[axis].map(|value| Value { value, span: given.get(axis).map_or(span, |v| v.span) });
        Ok(Axes { x: value(0), y: value(1), z: value(2) })
    }
}

#[cfg(test)]
mod tests {
    use crate::config::Config;
    use crate::passes::testing::run_with;
    use crate::statement::Dialect;

    fn entries(program: &str) -> Vec<String> {
        let config = Config { dialect: Dialect::Lenient.into(), ..Config::default() };
        run_with(program, &config, 4).into_iter().filter(|l| l.starts_with("G10") || l.contains("error")).collect()
    }

    #[test]
    fn l10_sets_an_entry_so_the_tool_reads_the_coordinates_given() {
        // LinuxCNC's own test (g10-l1-l10) says what each should be: from
        // (.1, .2, .3) with entry 1 zero and applied, X1 gives -.9; the axes
        // not given keep their entry; after G49 the offset in force is none.
        let got = entries(
            "G10 L1 P1 X0 Y0 Z0\nT1 M6\nG43\nG0 X.1 Y.2 Z.3\nG10 L10 P1 X1\nG43\nG10 L10 P1 Y2\nG10 L10 P1 Z3\n\
             G49\nG10 L10 P1 X0 Y0 Z0\nG10 L10 P1 X1",
        );
        assert_eq!(
            got,
            [
                "G10 L1 P1 X0.0000 Y0.0000 Z0.0000",
                "G10 L1 P1 X-0.9000",
                "G10 L1 P1 Y-1.8000",
                "G10 L1 P1 Z-2.7000",
                // G43 and G49 do not move the machine: it is still where the
                // move put it with entry 1 zero, as LinuxCNC's test expects.
                "G10 L1 P1 X0.1000 Y0.2000 Z0.3000",
                "G10 L1 P1 X-0.9000",
            ]
        );
    }

    #[test]
    fn in_a_turned_frame_l10_writes_x_and_y_together() {
        // LinuxCNC's g10-l1-l10, its last part: G54 turned 45°, the tool at
        // its origin. X1 reads as the point (cos 45°, sin 45°) away: the
        // entry is minus that; then Y1 with X read through that entry (1):
        // the point (1, 1) turned, (0, 1.414), so the entry is (0, -1.414).
        let got = entries("G10 L2 P1 R45\nG0 X0 Y0 Z0\nG10 L10 P1 X0 Y0 Z0\nT1 M6\nG43\nG10 L10 P1 X1\nG10 L10 P1 Y1");
        assert_eq!(got[1..], ["G10 L1 P1 X-0.7071 Y-0.7071", "G10 L1 P1 X0.0000 Y-1.4142"]);
    }

    #[test]
    fn l11_reads_in_g59_3_and_leaves_g92_out() {
        // LinuxCNC's g10-l11: G59.3's Z is -27; from machine Z-30 a touch-off at Z0 is a length of -3, G92 or not.
        let got = entries("G10 L2 P9 X25 Y26 Z-27\nG54\nG92 Z5\nG53 G0 Z-30\nG10 L11 P1 Z0");
        assert_eq!(got, ["G10 L1 P1 Z-3.0000"]);
    }

    #[test]
    fn an_offset_the_controller_holds_leaves_l10_unknown() {
        let got = entries("T2 M6\nG43 H2\nG0 Z1\nG10 L10 P2 Z0");
        assert_eq!(got.len(), 1);
        assert!(
            got[0].contains("with the offset of entry 2 in force, which the controller's tool table holds"),
            "{got:?}"
        );
    }
}
