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
