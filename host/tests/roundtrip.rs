//! Property: ger's output, fed back into ger, translates to itself (N numbers
//! and the line naming the source aside), for generated programs that use
//! every feature of the translator; and a generated parametric program
//! (parameters, expressions, LinuxCNC's O-word loops, branches and calls,
//! Fanuc's WHILE) flattens to plain G-code that the strict dialect reads and
//! translates to the same moves.
//!
//! Programs are generated so that they are valid: arcs are written in
//! incremental mode from a centre offset and an angle, so the end lies on the
//! circle whatever the tool's absolute position.

use ger_core::config::{Config, WorkOffsets};
use ger_core::emit::{preamble, Emitter};
use ger_core::passes::{translate, Event, Library, Options, LAST_STAGE};
use ger_core::statement::Units;
use ger_core::wizard::NoWizards;
use proptest::prelude::*;

/// Translates `program`; panics on any diagnostic (generated programs are valid).
fn translated(program: &str, config: &Config) -> String {
    let library = Library::scanning(|| Library::scan(program.as_bytes(), &config.dialect));
    let emitter = Emitter::new(config.units.decimals(), true);
    let options = Options { config, stage: LAST_STAGE, wizards: &mut NoWizards };
    let mut out = preamble("generated", config.units);
    for event in translate(program.as_bytes(), library, options) {
        match event {
            Event::Statement(statement) => {
                out.push_str(&emitter.line(&statement));
                out.push('\n');
            }
            Event::Diagnostic(diagnostic) => panic!("{diagnostic}\nin:\n{program}"),
        }
    }
    out
}

/// The output without its N numbers and first (source-naming) line.
fn without_line_numbers(output: &str) -> Vec<String> {
    output
        .lines()
        .skip(1)
        .map(|line| match line.split_once(' ') {
            Some((n, rest)) if n.starts_with('N') => rest.to_string(),
            _ => line.to_string(),
        })
        .collect()
}

fn coordinate() -> impl Strategy<Value = String> {
    (-200_000i32..200_000).prop_map(|thousandths| format!("{:.3}", f64::from(thousandths) / 1000.0))
}

fn feed() -> impl Strategy<Value = String> {
    prop_oneof![Just(String::new()), (1u32..5000).prop_map(|f| format!(" F{f}"))]
}

/// One arc in incremental mode, in one of the three planes, by I/J/K or R.
fn arc() -> impl Strategy<Value = String> {
    (0usize..3, any::<bool>(), any::<bool>(), 100i32..100_000, 0.0f64..360.0, 0.0f64..360.0, -50_000i32..50_000, feed())
        .prop_map(|(plane, clockwise, by_radius, radius, from, sweep, normal, feed)| {
            let (code, [first, second, normal_letter], [first_centre, second_centre]) = [
                ("G17", ['X', 'Y', 'Z'], ['I', 'J']),
                ("G18", ['Z', 'X', 'Y'], ['K', 'I']),
                ("G19", ['Y', 'Z', 'X'], ['J', 'K']),
            ][plane];
            // At least 0.1: below the arc tolerance (0.01 mm) a radius counts as zero.
            let r = f64::from(radius) / 1000.0;
            let (from, to) = (from.to_radians(), (from + sweep.max(1.0)).to_radians());
            // Start and end on a circle about the origin; the move is their difference.
            let (ca, sa) = (r * from.cos(), r * from.sin());
            let (da, db) = (r * to.cos() - ca, r * to.sin() - sa);
            let mut text =
                format!("{code}\nG91\n{} {first}{da:.6} {second}{db:.6}", if clockwise { "G02" } else { "G03" });
            if by_radius && da.hypot(db) > 1e-3 {
                // The short or the long arc with that chord: either is valid.
                text += &format!(" R{}", if sweep > 180.0 { -r } else { r });
            } else {
                text += &format!(" {first_centre}{:.6} {second_centre}{:.6}", -ca, -sa);
            }
            text + &format!(" {normal_letter}{:.3}{feed}\nG90", f64::from(normal) / 1000.0)
        })
}

fn statement() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (coordinate(), coordinate(), coordinate()).prop_map(|(x, y, z)| format!("G00 X{x} Y{y} Z{z}")),
        4 => (coordinate(), coordinate(), feed()).prop_map(|(x, y, f)| format!("G01 X{x} Y{y}{f}")),
        2 => (coordinate(), coordinate()).prop_map(|(x, z)| format!("G91\nG01 X{x} Z{z}\nG90")),
        4 => arc(),
        1 => (coordinate(), 0u32..360).prop_map(|(r, a)| format!("G17\nG91\nG16\nG01 X{r} Y{a}\nG15\nG90")),
        1 => prop_oneof![Just("G20"), Just("G21")].prop_map(String::from),
        1 => (coordinate(), coordinate(), coordinate()).prop_map(|(x, y, z)| format!("G52 X{x} Y{y} Z{z}")),
        1 => (coordinate(), coordinate()).prop_map(|(x, y)| format!("G92 X{x} Y{y}")),
        1 => (54u32..=59).prop_map(|n| format!("G{n}")),
        // G43's Z is a move in the mode in force: in G02 it would be an arc.
        1 => (coordinate(), 1u32..20).prop_map(|(z, h)| format!("G00 G43 Z{z} H{h}")),
        1 => prop_oneof![Just("M03 S12000"), Just("M05"), Just("M08"), Just("M09"), Just("M06 T2"), Just("G49")]
            .prop_map(String::from),
        1 => (1u32..4).prop_map(|l| format!("M98 P7 L{l}")),
    ]
}

fn program() -> impl Strategy<Value = String> {
    (proptest::collection::vec(statement(), 1..40), proptest::collection::vec(statement(), 0..6)).prop_map(
        |(main, sub)| {
            // The subprogram may not call itself; everything else may appear in it.
            let sub: Vec<String> = sub.into_iter().filter(|s| !s.starts_with("M98")).collect();
            format!("G01 F100\n{}\nM30\nO7\n{}\nM99\n", main.join("\n"), sub.join("\n"))
        },
    )
}

fn seed() -> proptest::test_runner::RngSeed {
    let fixed = std::env::var("PROPTEST_RNG_SEED").ok().and_then(|s| s.parse().ok()).unwrap_or(0x6765_7220);
    proptest::test_runner::RngSeed::Fixed(fixed)
}

fn machines() -> impl Strategy<Value = Config> {
    prop_oneof![Just(Units::Inch), Just(Units::Mm)].prop_map(|units| Config {
        units,
        offsets: WorkOffsets {
            g54: Some([1.0, 2.0, 3.0]),
            g56: Some([-10.5, 0.25, 0.0]),
            g59: Some([100.0, -100.0, -1.0]),
            ..WorkOffsets::default()
        },
        ..Config::default()
    })
}

proptest! {
    // A fixed seed: the same 300 programs every run, so CI is repeatable.
    // PROPTEST_RNG_SEED=<n> explores others.
    #![proptest_config(ProptestConfig {
        cases: 300,
        rng_seed: seed(),
        ..ProptestConfig::default()
    })]

    #[test]
    fn the_output_translates_to_itself(program in program(), config in machines()) {
        let once = translated(&program, &config);
        let twice = translated(&once, &config);
        prop_assert_eq!(without_line_numbers(&once), without_line_numbers(&twice), "program:\n{}", program);
    }
}

fn weight() -> impl Strategy<Value = String> {
    (1u32..50).prop_map(|w| format!("{:.1}", f64::from(w) / 10.0))
}

/// A lenient spline: G5 (alone or two in a series), G5.1, or a NURBS of order 3 to 5.
fn spline() -> impl Strategy<Value = String> {
    let point = || (coordinate(), coordinate());
    prop_oneof![
        (point(), point(), point(), any::<bool>(), point(), point()).prop_map(
            |((i, j), (p, q), (x, y), series, (p2, q2), (x2, y2))| {
                let first = format!("G05 I{i} J{j} P{p} Q{q} X{x} Y{y}");
                if series {
                    format!("{first}\nG05 P{p2} Q{q2} X{x2} Y{y2}")
                } else {
                    first
                }
            }
        ),
        (point(), point()).prop_map(|((i, j), (x, y))| format!("G5.1 I{i} J{j} X{x} Y{y}")),
        (3usize..=5, proptest::collection::vec((point(), weight()), 4..8)).prop_map(|(order, points)| {
            let lines: Vec<String> = points.iter().map(|((x, y), w)| format!("X{x} Y{y} P{w}")).collect();
            format!("G5.2 {} L{order}\n{}\nG5.3", lines[0], lines[1..].join("\n"))
        }),
    ]
}

fn spline_program() -> impl Strategy<Value = String> {
    let statement = prop_oneof![
        3 => spline(),
        1 => (coordinate(), coordinate()).prop_map(|(x, y)| format!("G01 X{x} Y{y}")),
        1 => prop_oneof![Just("G20"), Just("G21"), Just("G91"), Just("G90")].prop_map(String::from),
    ];
    proptest::collection::vec(statement, 1..6).prop_map(|lines| format!("G01 F100\n{}\nG90\nM30\n", lines.join("\n")))
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        rng_seed: seed(),
        ..ProptestConfig::default()
    })]

    /// The arcs and lines splines become pass ger's own arc checks, rounded
    /// as written, and translate to themselves.
    #[test]
    fn splines_translate_to_output_that_translates_to_itself(program in spline_program(), machine in machines()) {
        let lenient = Config { dialect: ger_core::statement::Dialect::Lenient.into(), ..machine.clone() };
        let once = translated(&program, &lenient);
        let twice = translated(&once, &machine);
        prop_assert_eq!(without_line_numbers(&once), without_line_numbers(&twice), "program:\n{}", program);
    }
}

/// A value that stays small however it is combined: a number, one of
/// #1 to #4 (which only ever hold such values), or a sine of anything.
fn term() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        (-500i32..500).prop_map(|n| format!("{:.1}", f64::from(n) / 10.0)),
        (1u32..=4).prop_map(|k| format!("#{k}")),
        Just("#<depth>".to_string()),
    ];
    leaf.prop_recursive(3, 12, 2, |inner| {
        prop_oneof![
            (inner.clone(), prop_oneof![Just('+'), Just('-'), Just('*')], inner.clone())
                .prop_map(|(a, op, b)| format!("[{a} {op} {b}]")),
            (prop_oneof![Just("SIN"), Just("COS"), Just("ABS")], inner).prop_map(|(f, a)| format!("{f}[{a}]")),
        ]
    })
}

/// A block of a parametric program, LinuxCNC's and Fanuc's constructs both,
/// nested `depth` deep at most; `label` keeps O-word labels apart.
fn parametric(depth: u32) -> BoxedStrategy<String> {
    let plain = prop_oneof![
        3 => (1u32..=4, term()).prop_map(|(k, e)| format!("#{k} = [20 * SIN[{e}]]")),
        4 => (term(), term()).prop_map(|(x, y)| format!("G01 X[{x}] Y[{y}]")),
        1 => term().prop_map(|z| format!("G00 Z[ABS[{z}] + 1]")),
        1 => (term(), term()).prop_map(|(a, b)| format!("o900 call [{a}] [{b}]")),
        1 => (term(), term()).prop_map(|(x, y)| format!("#<depth> = [20 * SIN[{x}]]\nG01 X#<depth> Y[{y} + #<depth>]")),
    ];
    if depth == 0 {
        return plain.boxed();
    }
    let body = || proptest::collection::vec(parametric(depth - 1), 1..4).prop_map(|lines| lines.join("\n"));
    let label = 100 + depth;
    prop_oneof![
        4 => plain,
        1 => (1u32..4, body()).prop_map(move |(n, b)| format!("o{label} repeat [{n}]\n{b}\no{label} endrepeat")),
        1 => (term(), body(), body())
            .prop_map(move |(c, a, b)| format!("o{label} if [{c} GT 0]\n{a}\no{label} else\n{b}\no{label} endif")),
        1 => (1u32..4, body()).prop_map(move |(n, b)| {
            format!("#{} = 0\no{label} while [#{0} LT {n}]\n{b}\n#{0} = [#{0} + 1]\no{label} endwhile", 10 + depth)
        }),
        1 => (1u32..4, body()).prop_map(move |(n, b)| {
            format!("#{} = 0\nWHILE [#{0} LT {n}] DO{depth}\n{b}\n#{0} = #{0} + 1\nEND{depth}", 20 + depth)
        }),
    ]
    .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 96,
        rng_seed: seed(),
        ..ProptestConfig::default()
    })]

    /// A parametric program (lenient) flattens to plain G-code that the
    /// strict dialect reads and that translates to the same moves.
    #[test]
    fn a_parametric_program_and_its_flattened_output_make_the_same_moves(
        body in proptest::collection::vec(parametric(2), 1..12),
        start in proptest::collection::vec(term(), 4),
    ) {
        let parameters: String = start.iter().enumerate().map(|(k, e)| format!("#{} = [20 * COS[{e}]]\n", k + 1)).collect();
        let program = format!(
            "G21 G90 G17 F200\n#<depth> = 1\n{parameters}{}\nM30\no900 sub\nG01 X[#1 * 2] Y[#2 - #1]\no900 endsub\n",
            body.join("\n")
        );
        let lenient = Config { units: Units::Mm, dialect: ger_core::statement::Dialect::Lenient.into(), ..Config::default() };
        let strict = Config { units: Units::Mm, ..Config::default() };
        let once = translated(&program, &lenient);
        let twice = translated(&once, &strict);
        prop_assert_eq!(without_line_numbers(&once), without_line_numbers(&twice), "program:\n{}", program);
    }
}
