//! The interpreter stage's speed (`cargo bench -p ger-core --bench flatten`):
//! three nested loops (100 x 100 x 100) making 1,000,000 moves, as LinuxCNC
//! O-words and as Fanuc macro B, flattened to statements by `passes::parse`
//! (lexer, interpreter stage, parser), best of three by the clock. The whole
//! translation, with its peak memory, is `host/bench/macros.sh`.

use std::time::{Duration, Instant};

use ger_core::config::DialectConfig;
use ger_core::passes::{parse, Event};
use ger_core::statement::{Dialect, Kind};

const LINUXCNC: &str = "G21 G90 G17 F1000
#1 = 0
o100 while [#1 LT 100]
  #2 = 0
  o101 while [#2 LT 100]
    #3 = 0
    o102 while [#3 LT 100]
      G01 X[#3 * 0.5] Y[#2 * 0.5] Z[-0.01 * #1]
      #3 = [#3 + 1]
    o102 endwhile
    #2 = [#2 + 1]
  o101 endwhile
  #1 = [#1 + 1]
o100 endwhile
M30
";

const FANUC: &str = "G21 G90 G17 F1000
#1 = 0
WHILE [#1 LT 100] DO1
#2 = 0
WHILE [#2 LT 100] DO2
#3 = 0
WHILE [#3 LT 100] DO3
G01 X[#3 * 0.5] Y[#2 * 0.5] Z[-0.01 * #1]
#3 = #3 + 1
END3
#2 = #2 + 1
END2
#1 = #1 + 1
END1
M30
";

fn flatten(program: &str, dialect: &DialectConfig) -> usize {
    parse(program.as_bytes(), dialect)
        .filter(|event| match event {
            Event::Statement(statement) => matches!(&statement.kind, Kind::Motion(motion) if motion.moves()),
            Event::Diagnostic(diagnostic) => panic!("{diagnostic}"),
        })
        .count()
}

fn main() {
    let mut dialect: DialectConfig = Dialect::Lenient.into();
    // The outer loop makes every move.
    dialect.limits.iterations = 100_000_000;
    for (name, program) in [("LinuxCNC O-words", LINUXCNC), ("Fanuc macro B", FANUC)] {
        let mut best = Duration::MAX;
        let mut moves = 0;
        for _ in 0..3 {
            let start = Instant::now();
            moves = flatten(program, &dialect);
            best = best.min(start.elapsed());
        }
        assert_eq!(moves, 1_000_000);
        let rate = moves as f64 / best.as_secs_f64();
        println!("{name:<18} {moves} moves flattened in {best:>8.2?}: {rate:>10.0} moves/s");
    }
}
