//! The program-level API, on small programs whose answers are worked out by hand.

use std::io::Write as _;

use ger_core::config::Config;
use ger_core::passes::{Event, LAST_STAGE};
use ger_core::statement::Units;
use ger_render::pieces::PieceKind;
use ger_sim::{Point, Stock};

use crate::{ConfigError, Culprit, Program, Progress, Purpose, Resolution, Settings, Silent, Source};

/// A slot 2 in long and 0.1 in deep with tool 1 (a quarter inch by default).
const SLOT: &str = "G20 G90\nM06 T1\nM03 S10000\nG00 X0 Y0 Z0.1\nG01 Z-0.1 F30\nG01 X2\nG00 Z0.5\nM30\n";

fn slot() -> Program {
    Program::new(Source::text("slot.nc", ".", SLOT), Config::default())
}

fn statements(program: &mut Program, stage: u8) -> Vec<String> {
    let emitter = ger_core::emit::Emitter::new(4, false);
    program
        .events(stage)
        .filter_map(|event| match event {
            Event::Statement(statement) => Some(emitter.line(&statement)),
            Event::Diagnostic(_) => None,
        })
        .collect()
}

#[test]
fn events_are_the_translation_after_the_pass_asked_for() {
    // In a mm machine, the inch program is in inches until pass 01 converts it.
    let config = Config { units: Units::Mm, ..Config::default() };
    let mut program = Program::new(Source::text("slot.nc", ".", SLOT), config);
    let before = statements(&mut program, 0);
    let after = statements(&mut program, LAST_STAGE);
    assert!(before.iter().any(|line| line.contains("X2")), "{before:?}");
    assert!(after.iter().any(|line| line.contains("X50.8")), "{after:?}");
}

#[test]
fn the_translation_as_text_is_a_line_a_statement() {
    let mut program = slot();
    let mut text = String::new();
    let report = program
        .write_translation(LAST_STAGE, true, |line| {
            text.push_str(line);
            Ok(())
        })
        .unwrap();
    assert_eq!(report.errors(), 0);
    assert!(text.lines().any(|line| line.starts_with("N6 G01 X2.0000")), "{text}");
}

#[derive(Default)]
struct Recorder {
    log: Vec<String>,
    total: u64,
    most: u64,
}

impl Progress for Recorder {
    fn begin(&mut self, job: &'static str, total: u64) {
        self.log.push(format!("begin {job}"));
        self.total = total;
    }

    fn advance(&mut self, done: u64) {
        assert!(done <= self.total, "{done} of {}", self.total);
        self.most = self.most.max(done);
    }

    fn end(&mut self) {
        self.log.push("end".into());
    }
}

#[test]
fn progress_is_told_of_each_pass_over_the_program() {
    let mut program = slot();
    let mut progress = Recorder::default();
    let (stock, report) = program.stock(&mut progress);
    assert_eq!(report.errors(), 0);
    let simulation = program.simulation(stock, Resolution { cell: Some(0.01), ..Resolution::default() }).unwrap();
    let (_part, report) = program.simulate(simulation, &mut progress);
    assert_eq!(report.errors(), 0);
    assert_eq!(progress.log, ["begin bounds", "end", "begin cutting", "end"]);
    assert_eq!(progress.total, SLOT.len() as u64);
}

/// Stops the pass once told of `after` bytes read.
struct StopAfter(u64, u64);

impl Progress for StopAfter {
    fn advance(&mut self, done: u64) {
        self.1 = done;
    }

    fn stopped(&self) -> bool {
        self.1 >= self.0
    }
}

#[test]
fn a_pass_stops_when_its_progress_says_so() {
    // 10,000 moves, each its own statement: progress is asked every 4096 events.
    let text: String = (0..10_000).map(|i| format!("G01 X{} F10\n", i % 7)).collect();
    let mut program = Program::new(Source::text("long.nc", ".", text), Config::default());
    let count = |program: &mut Program, progress: &mut dyn Progress| {
        let mut events = 0;
        program.for_each_event("checking", progress, |_| {
            events += 1;
            true
        });
        events
    };
    assert_eq!(count(&mut program, &mut Silent), 10_000);
    // Asked after the first event, it stops there; wanting 1000 bytes read
    // (90 lines of 11 bytes), it stops at the next asking, after event 4097.
    assert_eq!(count(&mut program, &mut StopAfter(0, 0)), 1);
    assert_eq!(count(&mut program, &mut StopAfter(1000, 0)), 4097);
}

#[test]
fn the_stock_by_margin_is_the_cut_and_the_part_has_the_slot() {
    let mut program = slot();
    let (stock, _) = program.stock(&mut Silent);
    // The cut's box, the tool's radius either side of the path, with the default margin of 0.1 in.
    let (margin, r) = (0.1, 0.125);
    let expected = Stock {
        min: Point::new(-r - margin, -r - margin, -0.1 - margin),
        max: Point::new(2.0 + r + margin, r + margin, 0.0),
    };
    assert!(stock.min.distance(expected.min) < 1e-9 && stock.max.distance(expected.max) < 1e-9, "{stock:?}");
    let simulation = program.simulation(stock, Resolution { cell: Some(0.01), ..Resolution::default() }).unwrap();
    let (part, _) = program.simulate(simulation, &mut Silent);
    let (i, j) = (((1.0 - stock.min.x) / part.cell) as usize, ((0.0 - stock.min.y) / part.cell_y()) as usize);
    // Heights are kept in f32.
    assert!((part.get(i, j) + 0.1).abs() < 1e-6, "the slot's floor: {}", part.get(i, j));
    let beside = ((0.2 - stock.min.y) / part.cell_y()) as usize;
    assert_eq!(part.get(i, beside), 0.0, "beside the slot, the stock's top");
}

#[test]
fn a_simulation_too_fine_for_memory_says_whose_number_it_was() {
    let mut program = slot();
    let (stock, _) = program.stock(&mut Silent);
    let asked = Resolution { cell: Some(1e-4), memory_limit_mib: Some(1) };
    let refused = program.simulation(stock, asked).err().expect("too fine for 1 MiB");
    assert_eq!(refused.by, Culprit::Caller);
    assert!(refused.message.contains("the finest that fits is --resolution"), "{}", refused.message);

    let mut config = Config::default();
    config.render.scale = Some(10_000.0);
    config.render.memory_limit_mb = Some(1);
    let program = Program::new(Source::text("slot.nc", ".", SLOT), config);
    let refused = program.simulation(stock, Resolution::default()).err().expect("too fine for 1 MiB");
    assert_eq!(refused.by, Culprit::Config("scale"));
}

#[test]
fn the_toolpath_is_every_move_and_its_pieces_keep_to_the_tolerance() {
    let mut program = slot();
    let mut moves = Vec::new();
    program.toolpath(|m| {
        moves.push((m.segment.to(), m.rapid));
        true
    });
    let ends: Vec<(Point, bool)> = vec![
        (Point::new(0.0, 0.0, 0.1), true),
        (Point::new(0.0, 0.0, -0.1), false),
        (Point::new(2.0, 0.0, -0.1), false),
        (Point::new(2.0, 0.0, 0.5), true),
    ];
    assert_eq!(moves, ends);

    let arc = "G20 G90\nG00 X1 Y0\nG03 X-1 Y0 I-1 J0 F10\nM30\n";
    let mut program = Program::new(Source::text("arc.nc", ".", arc), Config::default());
    let (pieces, report) = program.toolpath_pieces(0.001);
    assert_eq!(report.errors(), 0);
    assert_eq!(pieces[0].kind, PieceKind::Rapid);
    let chords = &pieces[1..];
    // A half circle of radius 1 within 0.001: each chord's sagitta is at most that.
    let step = 2.0 * (1.0f64 - 0.001).acos();
    assert_eq!(chords.len(), (std::f64::consts::PI / step).ceil() as usize);
    for piece in chords {
        let middle = [(piece.from[0] + piece.to[0]) / 2.0, (piece.from[1] + piece.to[1]) / 2.0];
        let sagitta = 1.0 - f64::from(middle[0]).hypot(f64::from(middle[1]));
        assert!(sagitta <= 0.001 + 1e-6, "{piece:?}");
    }
}

#[test]
fn the_machine_is_the_config_beside_the_program_with_the_settings_over_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut file = std::fs::File::create(dir.path().join("ger.toml")).unwrap();
    writeln!(file, "units = \"mm\"").unwrap();
    let source = Source::text("part.nc", dir.path(), SLOT);
    let config = Settings::default().load(&source, Purpose::Translate).unwrap();
    assert_eq!(config.units, Units::Mm);
    let overridden = Settings { units: Some(Units::Inch), lenient: true, ..Settings::default() };
    let config = overridden.load(&source, Purpose::Translate).unwrap();
    assert_eq!(config.units, Units::Inch);
    assert_eq!(config.dialect.name, ger_core::statement::Dialect::Lenient);

    std::fs::write(dir.path().join("ger.toml"), "units = \"furlongs\"\n").unwrap();
    let err = Settings::default().load(&source, Purpose::Translate).unwrap_err();
    assert!(matches!(err, ConfigError::Invalid { .. }), "{err:?}");
    let shown = err.render(false);
    assert!(shown.contains("ger.toml:1:"), "{shown}");
    assert!(shown.contains("bad configuration"), "{shown}");
}

#[test]
fn grbl_settings_are_read_from_beside_the_config_and_scaled_to_the_machine_unit() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("machine")).unwrap();
    std::fs::write(dir.path().join("ger.toml"), "[machine.motion]\ngrbl_settings = \"machine/grbl.txt\"\n").unwrap();
    std::fs::write(dir.path().join("machine/grbl.txt"), "$100=80.000\n$110=2540.000\n$122=50.8\nok\n").unwrap();
    let source = Source::text("part.nc", dir.path(), SLOT);
    let config = Settings::default().load(&source, Purpose::Translate).unwrap();
    let profile = config.motion_profile();
    // The settings are in millimetres, the machine in inches: 2540 mm/min is 100 in/min.
    assert!((profile.machine.max_rate[0] - 100.0).abs() < 1e-9, "{profile:?}");
    assert!((profile.machine.acceleration[2] - 2.0).abs() < 1e-9, "{profile:?}");
    assert!((profile.machine.steps_per_unit[0] - 80.0 * 25.4).abs() < 1e-9, "{profile:?}");
    assert_eq!(profile.grbl_settings.as_deref(), Some(std::path::Path::new("machine/grbl.txt")));

    // A bad line is an error in that file, at its line and column.
    std::fs::write(dir.path().join("machine/grbl.txt"), "$110=2540.000\n$111=fast\n").unwrap();
    let err = Settings::default().load(&source, Purpose::Translate).unwrap_err();
    let shown = err.render(false);
    assert!(shown.contains("grbl.txt:2:6"), "{shown}");
    assert!(shown.contains("`fast` is not a number"), "{shown}");
    // A missing one is an error naming it.
    std::fs::remove_file(dir.path().join("machine/grbl.txt")).unwrap();
    let err = Settings::default().load(&source, Purpose::Translate).unwrap_err();
    assert!(err.to_string().contains("grbl.txt"), "{err}");
}

#[test]
fn a_subroutine_the_program_does_not_define_is_read_from_its_file() {
    // LinuxCNC's SUBROUTINE_PATH: `o<frame> call` finds frame.ngc beside the program, then in the
    // folders of [dialect] subroutine_path (from the config's folder). Lines outside the sub in
    // its file are not run; its moves carry the line of the call.
    let dir = tempfile::tempdir().unwrap();
    let (programs, library) = (dir.path().join("jobs"), dir.path().join("lib"));
    std::fs::create_dir_all(&programs).unwrap();
    std::fs::create_dir_all(&library).unwrap();
    std::fs::write(programs.join("ger.toml"), "units = \"mm\"\n[dialect]\nsubroutine_path = [\"../lib\"]\n").unwrap();
    std::fs::write(library.join("frame.ngc"), "G00 X99\no<frame> sub\nG01 X#1 Y#2 F100\no<frame> endsub\nM02\n")
        .unwrap();
    std::fs::write(programs.join("hole.ngc"), "o<hole> sub\nG01 Z#1 F50\no<hole> endsub\n").unwrap();
    let text = "G21 G90\no<frame> call [10] [20]\no<hole> call [-3]\no<frame> call [1] [2]\nM30\n";
    let source = Source::text("part.ngc", &programs, text);
    let config = Settings::default().load(&source, Purpose::Translate).unwrap();
    assert_eq!(config.dialect.subroutine_path, [programs.join("../lib")]);
    let mut program = Program::new(source, config);
    let lines: Vec<String> = program
        .events(LAST_STAGE)
        .map(|event| match event {
            Event::Statement(statement) => {
                format!("{}: {}", statement.span.line, ger_core::emit::Emitter::new(3, false).line(&statement))
            }
            Event::Diagnostic(diagnostic) => diagnostic.to_string(),
        })
        .collect();
    assert_eq!(
        lines,
        ["2: G01 X10.000 Y20.000 F100.000", "3: G01 Z-3.000 F50.000", "4: G01 X1.000 Y2.000 F100.000", "5: M30"]
    );

    // Not found anywhere: the error says where it looked.
    let source = Source::text("part.ngc", &programs, "o<nowhere> call\nM30\n");
    let config = Settings::default().load(&source, Purpose::Translate).unwrap();
    let mut program = Program::new(source, config);
    let errors: Vec<String> = program
        .events(LAST_STAGE)
        .filter_map(|event| match event {
            Event::Diagnostic(d) if d.is_error() => Some(format!("{d} {}", d.help.clone().unwrap_or_default())),
            _ => None,
        })
        .collect();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(errors[0].contains("o<nowhere> is called but never defined"), "{errors:?}");
    assert!(errors[0].contains("nowhere.ngc beside it or in a folder of [dialect] subroutine_path"), "{errors:?}");
}

/// A binary STL of quads, each given counter-clockwise seen from outside the solid.
fn binary_stl(quads: &[[[f64; 3]; 4]]) -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&(2 * quads.len() as u32).to_le_bytes());
    for &[a, b, c, d] in quads {
        for triangle in [[a, b, c], [a, c, d]] {
            bytes.extend_from_slice(&[0u8; 12]);
            for v in triangle {
                for x in v {
                    bytes.extend_from_slice(&(x as f32).to_le_bytes());
                }
            }
            bytes.extend_from_slice(&[0, 0]);
        }
    }
    bytes
}

/// The design: a 100 x 50 x 20 mm block (Z -20 to 0) with a slot 10 mm wide
/// and 5 deep along X, from Y 20 to 30, through both ends. Its faces meet
/// edge to edge: every face is cut where a neighbour's edge ends.
fn slotted_block() -> Vec<u8> {
    let (ys, zs) = ([0.0, 20.0, 30.0, 50.0], [-20.0, -5.0, 0.0]);
    let mut quads = Vec::new();
    // The bottom, in three strips; the top, either side of the slot; the slot's floor.
    for k in 0..3 {
        let (y0, y1) = (ys[k], ys[k + 1]);
        quads.push([[0.0, y0, -20.0], [0.0, y1, -20.0], [100.0, y1, -20.0], [100.0, y0, -20.0]]);
        let z = if k == 1 { -5.0 } else { 0.0 };
        quads.push([[0.0, y0, z], [100.0, y0, z], [100.0, y1, z], [0.0, y1, z]]);
    }
    // The long sides, each in two bands (Z -20 to -5, -5 to 0); the slot's walls.
    for band in 0..2 {
        let (z0, z1) = (zs[band], zs[band + 1]);
        quads.push([[0.0, 0.0, z0], [100.0, 0.0, z0], [100.0, 0.0, z1], [0.0, 0.0, z1]]);
        quads.push([[100.0, 50.0, z0], [0.0, 50.0, z0], [0.0, 50.0, z1], [100.0, 50.0, z1]]);
    }
    quads.push([[100.0, 20.0, -5.0], [0.0, 20.0, -5.0], [0.0, 20.0, 0.0], [100.0, 20.0, 0.0]]);
    quads.push([[0.0, 30.0, -5.0], [100.0, 30.0, -5.0], [100.0, 30.0, 0.0], [0.0, 30.0, 0.0]]);
    // The ends: a grid of Y by Z cells but the slot's.
    for k in 0..3 {
        for band in 0..2 {
            if k == 1 && band == 1 {
                continue;
            }
            let (y0, y1, z0, z1) = (ys[k], ys[k + 1], zs[band], zs[band + 1]);
            quads.push([[0.0, y1, z0], [0.0, y0, z0], [0.0, y0, z1], [0.0, y1, z1]]);
            quads.push([[100.0, y0, z0], [100.0, y1, z0], [100.0, y1, z1], [100.0, y0, z1]]);
        }
    }
    binary_stl(&quads)
}

fn compare(text: &str, tool: &str) -> crate::compare::Comparison {
    let toml = format!(
        "units = \"mm\"\n[stock]\nsize = [100, 50, 20]\norigin = [0, 0, 20]\n\
         [[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = {tool}\nflute_length = 20\n"
    );
    let config = Config::from_toml(&toml).unwrap();
    let mut design = crate::compare::Design::read(&mut std::io::Cursor::new(slotted_block())).unwrap();
    let mut program = Program::new(Source::text("slot.nc", ".", text), config.clone());
    let (stock, _) = program.stock(&mut Silent);
    crate::place_design(&mut design, &config, Units::Mm, None, &stock);
    let sim = program.simulation(stock, Resolution { cell: Some(0.1), ..Resolution::default() }).unwrap();
    program.compare(sim, &design, 0.05, &mut Silent).0.comparison
}

#[test]
fn the_part_against_its_design_exact_gouged_and_with_a_rib_left() {
    // A 10 mm endmill along the slot's middle, from outside the block to outside it.
    let exact = "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG01 Z-5 F500\nX110\nG00 Z5\nM30\n";
    let c = compare(exact, "10");
    assert_eq!((c.gouge.area, c.left.area, c.gouge.worst, c.left.worst), (0.0, 0.0, 0.0, 0.0), "{c:?}");
    assert!((c.judged_area - 5000.0).abs() < 1e-6, "{}", c.judged_area);

    // Then 0.3 mm deeper from X50 to X70 (lines 7 and 8; the retract, line 9, cuts nothing): a
    // stadium 20 x 10 mm with round ends, 200 + 25 pi mm², 0.3 mm deep.
    let deep = "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG01 Z-5 F500\nX110\nG00 X50 Z1\nG01 Z-5.3\nX70\nG00 Z5\nM30\n";
    let c = compare(deep, "10");
    let area = 200.0 + 25.0 * std::f64::consts::PI;
    assert!((c.gouge.worst - 0.3).abs() < 1e-5, "{:?}", c.gouge);
    let [x, y] = c.gouge.at.unwrap();
    assert!((45.0..=75.0).contains(&x) && (20.0..=30.0).contains(&y), "{:?}", c.gouge.at);
    assert!((c.gouge.area - area).abs() / area < 0.02, "{} vs {area}", c.gouge.area);
    assert!((c.gouge.volume - 0.3 * area).abs() / (0.3 * area) < 0.02, "{:?}", c.gouge);
    assert_eq!(c.gouge.lines, [7, 8]);
    assert_eq!(c.left.area, 0.0);

    // A 4 mm endmill along Y22 and Y28 leaves a rib 2 mm wide, 5 high and 100 long between: 1000 mm³.
    let rib = "G21\nM03 S10000\nG00 X-10 Y22 Z1\nG01 Z-5 F500\nX110\nG00 Z1\nX-10 Y28\nG01 Z-5\nX110\nG00 Z5\nM30\n";
    let c = compare(rib, "4");
    assert!((c.left.volume - 1000.0).abs() / 1000.0 < 0.02, "{:?}", c.left);
    assert!((c.left.worst - 5.0).abs() < 1e-5 && c.gouge.area == 0.0, "{c:?}");
}

#[test]
fn a_finishing_program_after_its_roughing_is_judged_against_what_roughing_left() {
    let config = Config::from_toml(
        "units = \"mm\"\n[stock]\nsize = [100, 50, 20]\norigin = [0, 0, 20]\n\
         [[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 6\nflute_length = 10\n",
    )
    .unwrap();
    // Roughing: a slot along Y20 from X20 to X40, 4.5 mm deep in two passes.
    let rough = "G21\nM03 S10000\nG00 X20 Y20 Z1\nG01 Z-2 F200\nX40\nZ-4.5\nX20\nG00 Z5\nM30\n";
    // Finishing: a rapid down to Z-4 in the slot (line 4), then the last half millimetre.
    let finish = "G21\nM03 S10000\nG00 X30 Y20 Z1\nG00 Z-4\nG01 Z-5 F100\nX20\nX40\nG00 Z5\nM30\n";
    let program = |name, text| Program::new(Source::text(name, ".", text), config.clone());
    let cell = Resolution { cell: Some(0.1), ..Resolution::default() };
    let messages = |verdict: &ger_check::Verdict| -> Vec<String> {
        verdict.findings.iter().map(|f| format!("{}: {}", f.diagnostic.span.line, f.diagnostic.message)).collect()
    };

    // Alone, on a fresh block, its rapid goes 4 mm into the stock.
    let mut alone = program("finish.nc", finish);
    let (stock, _) = alone.stock(&mut Silent);
    let (verdict, _) = alone.check(alone.simulation(stock, cell).unwrap(), &[], &mut Silent);
    assert_eq!(messages(&verdict), ["4: rapid move (G00) cuts 4.000 mm into the stock"]);

    // After the roughing, in the air it left.
    let mut job = crate::Job::new(program("rough.nc", rough), vec![program("finish.nc", finish)]);
    let (stock, _) = job.stock(&mut Silent);
    let (verdicts, part) = job.check(job.simulation(stock, cell).unwrap(), &[], &mut Silent);
    assert_eq!(verdicts.len(), 2);
    assert!(verdicts.iter().all(|v| v.findings.is_empty()), "{:?}", verdicts.iter().map(messages).collect::<Vec<_>>());
    // The part is both programs' cut: 5 mm deep where the finishing pass went.
    assert!((part.lowest() + 5.0).abs() < 1e-6, "{}", part.lowest());
    // Each summary's cut is the part as that program leaves it: 4.5 mm deep, then 5.
    assert_eq!(verdicts[0].summary.cut_box.unwrap().min[2], -4.5);
    assert_eq!(verdicts[1].summary.cut_box.unwrap().min[2], -5.0);
}

#[test]
fn a_job_is_compared_on_the_part_all_its_programs_leave_and_its_gouges_name_the_program() {
    let toml = "units = \"mm\"\n[stock]\nsize = [100, 50, 20]\norigin = [0, 0, 20]\n\
                [[tools]]\nnumber = 1\nkind = \"endmill\"\ndiameter = 10\nflute_length = 20\n";
    let config = Config::from_toml(toml).unwrap();
    let program = |name, text| Program::new(Source::text(name, ".", text), config.clone());
    // Roughing: the slot 4 mm deep of its 5. Finishing: a rapid down into the roughed slot (line 4),
    // the last millimetre, then 0.3 mm deeper from X50 to X70 (lines 8 and 9).
    let rough = "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG01 Z-4 F500\nX110\nG00 Z5\nM30\n";
    let finish =
        "G21\nM03 S10000\nG00 X-10 Y25 Z1\nG00 Z-3\nG01 Z-5 F500\nX110\nG00 X50 Z1\nG01 Z-5.3\nX70\nG00 Z5\nM30\n";
    let compare = |programs: Vec<Program>| {
        let mut programs = programs.into_iter();
        let mut job = crate::Job::new(programs.next().unwrap(), programs.collect());
        let mut design = crate::compare::Design::read(&mut std::io::Cursor::new(slotted_block())).unwrap();
        let (stock, _) = job.stock(&mut Silent);
        crate::place_design(&mut design, &config, Units::Mm, None, &stock);
        let sim = job.simulation(stock, Resolution { cell: Some(0.1), ..Resolution::default() }).unwrap();
        job.compare(sim, &design, 0.05, &mut Silent).0.comparison
    };

    // The roughing alone leaves the slot's last millimetre: 10 x 100 mm, 1000 mm³.
    let c = compare(vec![program("rough.nc", rough)]);
    assert!((c.left.worst - 1.0).abs() < 1e-5 && c.gouge.area == 0.0, "{c:?}");
    assert!((c.left.volume - 1000.0).abs() / 1000.0 < 0.02, "{:?}", c.left);

    // Both: the gouge of the finishing pass, 0.3 mm over the stadium 20 x 10 mm with round ends,
    // by the finishing program's lines alone (the roughing never went below the design).
    let c = compare(vec![program("rough.nc", rough), program("finish.nc", finish)]);
    let area = 200.0 + 25.0 * std::f64::consts::PI;
    assert!((c.gouge.worst - 0.3).abs() < 1e-5 && c.left.area == 0.0, "{c:?}");
    assert!((c.gouge.area - area).abs() / area < 0.02, "{} vs {area}", c.gouge.area);
    let cut_by: Vec<(&str, &[u32])> = c.gouge.cut_by.iter().map(|c| (c.file.as_str(), &c.lines[..])).collect();
    assert_eq!(cut_by, [("finish.nc", &[8, 9][..])]);
    assert!(c.gouge.lines.is_empty(), "a job's lines are by program: {:?}", c.gouge.lines);

    // One program's lines are also named plainly, as before.
    let c = compare(vec![program("finish.nc", finish)]);
    assert_eq!(c.gouge.lines, [8, 9]);
}
