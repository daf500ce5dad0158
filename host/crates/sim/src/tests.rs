//! The simulation measured: widths, depths, sections, areas and volumes
//! against what geometry says they must be.

use std::f64::consts::PI;

use super::*;
use ger_core::config::{StockConfig, ToolKind};
use ger_core::passes::testing;

fn config(kind: ToolKind, diameter: f64, tip_angle: Option<f64>) -> Config {
    Config {
        tools: vec![Tool { tip_angle, ..Tool::new(1, kind, diameter) }],
        stock: StockConfig { size: Some([2.0, 1.0, 0.5]), origin: Some([0.0, 0.0, 0.5]), ..StockConfig::default() },
        ..Config::default()
    }
}

/// The program cut in `config`'s stock at `cell` (default: 1000 cells along the longer side).
fn simulate(text: &str, config: &Config, cell: Option<f64>) -> HeightField {
    let stock = Stock::from_config(config).unwrap();
    let mut sim = Simulation::new(stock, cell.unwrap_or(stock.default_cell()), 1 << 30).unwrap();
    let mut tracker = Tracker::new(&config.tools);
    for statement in testing::statements_with(text, config) {
        if let Some(m) = tracker.step(&statement).unwrap() {
            sim.cut(&m.segment, &tracker.cutter().unwrap());
        }
    }
    sim.finish()
}

/// The cells of column `i` (along Y) as (y, height).
fn section_y(field: &HeightField, x: f64) -> Vec<(f64, f64)> {
    let i = ((x - field.stock.min[0]) / field.cell) as usize;
    (0..field.ny).map(|j| (field.centre(i, j)[1], field.get(i, j))).collect()
}

const SLOT: &str = "G20\nG00 Z0.1\nX0.5 Y0.5\nG01 Z-0.1 F10\nX1.5\nG00 Z0.1\n";

#[test]
fn an_endmill_slot_is_as_wide_as_the_tool_and_as_deep_as_programmed() {
    let field = simulate(SLOT, &config(ToolKind::Endmill, 0.25, None), None);
    let section = section_y(&field, 1.0);
    let cut: Vec<_> = section.iter().filter(|(_, z)| *z < 0.0).collect();
    for (y, z) in &cut {
        assert!((z + 0.1).abs() < 1e-6, "a flat floor at -0.1, not {z} at y={y}");
    }
    let width = cut.len() as f64 * field.cell_y();
    assert!((width - 0.25).abs() <= 1.01 * field.cell_y(), "width {width}");
    // Exactly the cells whose centres are under the tool.
    for (y, z) in &section {
        assert_eq!(*z < 0.0, (y - 0.5).abs() <= 0.125, "y={y} z={z}");
    }
    assert_eq!(field.lowest() as f32, -0.1);
}

#[test]
fn a_ballmill_slot_has_a_semicircular_section() {
    let field = simulate(SLOT, &config(ToolKind::Ballmill, 0.5, None), None);
    // The ball's centre runs at Z=0.15: the section is the circle's lower half, cut off at Z=0.
    for (y, z) in section_y(&field, 1.0) {
        let off = y - 0.5;
        let want = if off.abs() < 0.25 { (0.15 - (0.0625 - off * off).sqrt()).min(0.0) } else { 0.0 };
        assert!((z - want).abs() < 1e-6, "y={y}: {z} vs {want}");
    }
}

#[test]
fn a_drill_leaves_a_cone() {
    let text = "G20\nG00 X1 Y0.5 Z0.1\nG01 Z-0.3 F5\nG00 Z0.1\n";
    let field = simulate(text, &config(ToolKind::Drill, 0.5, Some(90.0)), None);
    for (y, z) in section_y(&field, 1.0 + field.cell / 2.0) {
        let r = (y - 0.5).hypot(field.cell / 2.0);
        let want = if r <= 0.25 { (-0.3 + r).min(0.0) } else { 0.0 };
        assert!((z - want).abs() < 1e-6, "r={r}: {z} vs {want}");
    }
}

fn cut_area(field: &HeightField) -> f64 {
    let mut cells = 0;
    for j in 0..field.ny {
        for i in 0..field.nx {
            cells += usize::from(field.get(i, j) < field.top());
        }
    }
    cells as f64 * field.cell * field.cell_y()
}

#[test]
fn full_circles_cut_the_right_area() {
    // A ring: a circle of radius 0.3 with a quarter-inch endmill.
    let ring = "G20\nG00 Z0.1\nX1.3 Y0.5\nG01 Z-0.1 F10\nG02 X1.3 Y0.5 I-0.3 J0\nG00 Z0.1\n";
    let field = simulate(ring, &config(ToolKind::Endmill, 0.25, None), None);
    let want = PI * (0.425f64.powi(2) - 0.175f64.powi(2));
    assert!((cut_area(&field) / want - 1.0).abs() < 0.01, "{} vs {want}", cut_area(&field));
    // A pocket: a circle of radius 0.1, cleared to a disc of radius 0.225.
    let pocket = "G20\nG00 Z0.1\nX1.1 Y0.5\nG01 Z-0.1 F10\nG03 X1.1 Y0.5 I-0.1 J0\nG00 Z0.1\n";
    let field = simulate(pocket, &config(ToolKind::Endmill, 0.25, None), None);
    let want = PI * 0.225f64.powi(2);
    assert!((cut_area(&field) / want - 1.0).abs() < 0.01, "{} vs {want}", cut_area(&field));
    assert!((field.removed_volume() / (want * 0.1) - 1.0).abs() < 0.01);
}

#[test]
fn cut_volumes_match_the_analytic_volume_within_one_percent() {
    let endmill = simulate(SLOT, &config(ToolKind::Endmill, 0.25, None), None);
    // A 1 in slot with round ends: a box and a disc, 0.1 deep.
    let want = (0.25 * 1.0 + PI * 0.125 * 0.125) * 0.1;
    assert!((endmill.removed_volume() / want - 1.0).abs() < 0.01, "{} vs {want}", endmill.removed_volume());
    // A 0.5 in ball 0.2 deep: the section is a circular segment of height 0.2.
    let ball = simulate(&SLOT.replace("Z-0.1", "Z-0.2"), &config(ToolKind::Ballmill, 0.5, None), None);
    let (r, h) = (0.25f64, 0.2f64);
    let segment = r * r * ((r - h) / r).acos() - (r - h) * (2.0 * r * h - h * h).sqrt();
    // The ends: a spherical cap's volume.
    let cap = PI * h * h * (3.0 * r - h) / 3.0;
    let want = segment * 1.0 + cap;
    assert!((ball.removed_volume() / want - 1.0).abs() < 0.01, "{} vs {want}", ball.removed_volume());
}

#[test]
fn helices_and_slanted_moves_cut_exactly_where_the_tool_went() {
    // A helix down with an endmill: the lowest point is where it ends.
    let text = "G20\nG00 Z0\nX1.3 Y0.5\nG02 X1.3 Y0.5 I-0.3 J0 Z-0.2 F10\nG00 Z0.1\n";
    let field = simulate(text, &config(ToolKind::Endmill, 0.25, None), None);
    assert!((field.lowest() + 0.2).abs() < 1e-6);
    // Opposite the end the path is half way down; the tool covers that point
    // until it has turned a further acos(1 - R^2 / 2r^2) radians.
    let i = ((0.7 - field.stock.min[0]) / field.cell) as usize;
    let j = ((0.5 - field.stock.min[1]) / field.cell_y()) as usize;
    let turn = (1.0 - 0.125f64.powi(2) / (2.0 * 0.09)).acos();
    let want = -0.1 - 0.2 * turn / (2.0 * PI);
    assert!((field.get(i, j) - want).abs() < 1e-3, "{} vs {want}", field.get(i, j));
    // A ramp with a ballmill: over a point, the ball is lowest a little after
    // passing it, s = 0.2 R / sqrt(1 + 0.2^2) further on (0.2: the slope).
    let ramp = "G20\nG00 Z0.1\nX0.5 Y0.5\nG01 Z0 F10\nX1.5 Z-0.2\nG00 Z0.1\n";
    let field = simulate(ramp, &config(ToolKind::Ballmill, 0.25, None), None);
    let i = (1.0 / field.cell) as usize;
    let j = (0.5 / field.cell_y()) as usize;
    let [x, y] = field.centre(i, j);
    let (r, s) = (0.125f64, 0.2 * 0.125 / 1.04f64.sqrt());
    let off = y - 0.5;
    let want = -0.2 * (x + s - 0.5) + r - (r * r - s * s - off * off).sqrt();
    assert!((field.get(i, j) - want).abs() < 1e-6, "{} vs {want}", field.get(i, j));
}

#[test]
fn a_tool_not_in_the_table_is_an_error_at_its_m06() {
    let config = config(ToolKind::Endmill, 0.25, None);
    let mut tracker = Tracker::new(&config.tools);
    let statements = testing::statements("G20\nM06 T7\nG01 X1 F10\n");
    let errors: Vec<Diagnostic> = statements.iter().filter_map(|s| tracker.step(s).err()).collect();
    assert_eq!(errors.len(), 1);
    assert_eq!(errors[0].span.line, 2);
    assert!(errors[0].message.contains("tool 7"), "{}", errors[0].message);
    assert!(tracker.cutter().is_none());
}

#[test]
fn a_resolution_too_fine_for_the_limit_names_the_finest_that_fits() {
    let stock = Stock { min: Point::new(0.0, 0.0, -1.0), max: Point::new(100.0, 100.0, 0.0) };
    let Some(Refusal::TooBig(err)) = Simulation::new(stock, 0.001, 64 << 20).err() else { panic!("not refused") };
    assert!(err.needed > 64 << 20);
    assert!(HeightField::bytes(&stock, err.finest) <= 64 << 20);
    assert!(HeightField::bytes(&stock, err.finest * 0.97) > 64 << 20);
    assert!(Simulation::new(stock, err.finest, 64 << 20).is_ok());
}

#[test]
fn a_margin_stock_is_the_box_of_the_cut_below_zero() {
    let config = config(ToolKind::Endmill, 0.25, None);
    let mut bounds = CutBounds::default();
    let mut tracker = Tracker::new(&config.tools);
    for statement in testing::statements(SLOT) {
        if let Some(m) = tracker.step(&statement).unwrap() {
            bounds.add(&m.segment, tracker.cutter().as_ref());
        }
    }
    let stock = bounds.stock(0.1);
    let want = Stock { min: Point::new(0.275, 0.275, -0.2), max: Point::new(1.725, 0.725, 0.0) };
    for i in 0..3 {
        assert!((stock.min[i] - want.min[i]).abs() < 1e-9 && (stock.max[i] - want.max[i]).abs() < 1e-9, "{stock:?}");
    }
    // Nothing below zero: a block under the moves.
    let mut bounds = CutBounds::default();
    bounds.add(&Segment::Line { from: Point::ZERO, to: Point::new(1.0, 1.0, 0.5) }, None);
    assert_eq!(bounds.stock(0.1), Stock { min: Point::new(-0.1, -0.1, -0.1), max: Point::new(1.1, 1.1, 0.0) });
}

/// Plunges, their retracts, repeats, deeper repeats, slanted and level lines
/// wandering over a stock of 4 x 2 tiles (some through its bottom), from a
/// fixed linear congruential sequence.
fn wandering_moves() -> Vec<Segment> {
    let mut state = 12345u64;
    let mut next = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut moves = Vec::new();
    let mut at = Point::new(1.0, 0.5, 0.2);
    for _ in 0..60 {
        let to = match (next() * 5.0) as usize {
            0 => at.with_z(-0.6 * next()),
            1 => at.with_z(0.2),
            2 => Point::new(2.0 * next(), next(), at[2]),
            3 => Point::new(2.0 * next(), next(), -0.3 * next()),
            _ => {
                // Back along the last move, or down it again a little deeper.
                let last = *moves.last().unwrap_or(&Segment::Line { from: at, to: at });
                let from = last.from();
                if next() < 0.5 {
                    from
                } else {
                    from - Point::Z * 0.01
                }
            }
        };
        moves.push(Segment::Line { from: at, to });
        at = to;
    }
    moves
}

#[test]
fn passing_over_cut_cells_and_repeats_leaves_what_every_move_cut() {
    let stock = Stock { min: Point::new(0.0, 0.0, -0.5), max: Point::new(2.0, 1.0, 0.0) };
    let moves = wandering_moves();
    for cutter in [Cutter { radius: 0.15, shape: Shape::Ball }, Cutter { radius: 0.2, shape: Shape::Flat }] {
        let mut sim = Simulation::new(stock, 0.01, 1 << 30).unwrap();
        for segment in &moves {
            sim.cut(segment, &cutter);
        }
        let field = sim.finish();
        assert_eq!((field.nx, field.ny), (200, 100));
        for j in 0..field.ny {
            for i in 0..field.nx {
                let [x, y] = field.centre(i, j);
                // Each move on its own, straight down by hand, the others by the kernel.
                let lowest = moves.iter().fold(f64::INFINITY, |low, segment| {
                    let (from, to) = (segment.from(), segment.to());
                    let off = (x - from[0]).hypot(y - from[1]);
                    let z = if from[0] == to[0] && from[1] == to[1] {
                        if off <= cutter.radius {
                            from[2].min(to[2]) + cutter.profile(off)
                        } else {
                            f64::INFINITY
                        }
                    } else {
                        Cut::line(from, to, cutter).low(x, y)
                    };
                    low.min(z)
                });
                let want = lowest.clamp(stock.min[2], stock.max[2]);
                let got = field.get(i, j);
                assert!((got - want).abs() < 1e-6, "{cutter:?} cell ({i}, {j}) at ({x}, {y}): {got} vs {want}");
            }
        }
    }
}

#[test]
fn a_repeated_cut_removes_nothing_and_reports_nothing_but_a_deeper_one_cuts() {
    let stock = Stock { min: Point::new(0.0, 0.0, -1.0), max: Point::new(1.0, 1.0, 0.0) };
    let cutter = Cutter { radius: 0.3, shape: Shape::Flat };
    let mut sim = Simulation::new(stock, 0.01, 1 << 30).unwrap().inspecting();
    let (up, down, deeper) = (Point::new(0.5, 0.5, 0.5), Point::new(0.5, 0.5, -0.2), Point::new(0.5, 0.5, -0.4));
    let line = |from, to| Segment::Line { from, to };
    let cut: Vec<bool> = [line(up, down), line(down, up), line(up, down), line(down, up), line(up, deeper)]
        .iter()
        .enumerate()
        .map(|(tag, segment)| sim.cut_tagged(segment, &cutter, tag as u32))
        .collect();
    assert_eq!(cut, [true, false, false, false, true]);
    sim.settle();
    let contacts: Vec<(u32, f32)> = sim.take_contacts().iter().map(|c| (c.tag, c.depth)).collect();
    assert_eq!(contacts, [(0, 0.2), (4, 0.2)]);
    assert_eq!(sim.settled_below(), 5);
    let field = sim.finish();
    let centre = field.get(50, 50);
    assert!((centre + 0.4).abs() < 1e-6, "{centre}");
}

#[test]
fn a_guard_meets_what_the_moves_before_left_and_cuts_nothing() {
    let stock = Stock { min: Point::new(0.0, 0.0, -1.0), max: Point::new(1.0, 1.0, 0.0) };
    let cell = 0.01;
    let mut sim = Simulation::new(stock, cell, 1 << 30).unwrap().inspecting();
    let flat = |radius| Cutter { radius, shape: Shape::Flat };
    let plunge = Segment::Line { from: Point::new(0.5, 0.5, 0.5), to: Point::new(0.5, 0.5, -0.5) };
    // A 0.2 shank 0.3 above a 0.1 cutter's tip; a holder 0.6 above it; the shank grown by 0.15 to warn.
    let guards = [
        Guard { cutter: flat(0.2), base: 0.3, near: false },
        Guard { cutter: flat(0.5), base: 0.6, near: false },
        Guard { cutter: flat(0.35), base: 0.15, near: true },
    ];
    assert!(sim.inspect(&plunge, &flat(0.1), &[], 0));
    // The same plunge again cuts nothing, but its shank's ring (0.1 to 0.2 from
    // the axis) goes 0.2 into the top; the holder stays 0.1 above it; the grown shank 0.35 in.
    assert!(sim.inspect(&plunge, &flat(0.1), &guards, 1));
    // A wider cutter clears the ring: the shank then meets nothing, the grown one still the top past 0.25.
    assert!(sim.inspect(&plunge, &flat(0.25), &[], 2));
    assert!(sim.inspect(&plunge, &flat(0.1), &guards, 3));
    sim.settle();
    let contacts = sim.take_contacts();
    let of = |tag| contacts.iter().find(|c| c.tag == tag).copied();
    let one = of(1).expect("move 1's guards report");
    assert_eq!((one.depth, one.clash.map(|c| c.1), one.near.map(|c| c.1)), (0.0, Some(0), Some(2)));
    assert!((one.clash.unwrap().0 - 0.2).abs() < 1e-6, "{one:?}");
    assert!((one.near.unwrap().0 - 0.35).abs() < 1e-6, "{one:?}");
    let three = of(3).expect("move 3's grown shank reports");
    assert_eq!((three.clash, three.near.map(|c| c.1)), (None, Some(2)));
    let field = sim.finish();
    // The guards cut nothing: the cell 0.15 from the axis was cut by move 2 only.
    let (i, j) = (((0.5 + 0.15) / cell) as usize, (0.5 / cell) as usize);
    assert!((field.get(i, j) + 0.5).abs() < 1e-6);
}

#[test]
fn a_carved_stock_is_cut_from_where_it_was_carved_to() {
    // A 1 x 1 block, its left half carved down to -0.5 (a casting's step), nothing at all over x > 0.9.
    let stock = Stock { min: Point::new(0.0, 0.0, -1.0), max: Point::new(1.0, 1.0, 0.0) };
    let mut sim = Simulation::new(stock, 0.01, 1 << 30).unwrap().inspecting();
    let (nx, ny) = (sim.field().nx, sim.field().ny);
    let heights: Vec<Option<f64>> = (0..nx * ny)
        .map(|k| {
            let x = sim.field().centre(k % nx, k / nx)[0];
            if x > 0.9 {
                None
            } else {
                Some(if x < 0.5 { -0.5 } else { 0.0 })
            }
        })
        .collect();
    sim.carve(&heights);
    let cutter = Cutter { radius: 0.1, shape: Shape::Flat };
    let plunge = |x: f64, z: f64| Segment::Line { from: Point::new(x, 0.5, 0.5), to: Point::new(x, 0.5, z) };
    // Down to -0.3 over the step: nothing there; over the top, 0.3 of material.
    sim.cut_tagged(&plunge(0.25, -0.3), &cutter, 0);
    sim.cut_tagged(&plunge(0.7, -0.3), &cutter, 1);
    sim.settle();
    let contacts: Vec<(u32, f32)> = sim.take_contacts().iter().map(|c| (c.tag, c.depth)).collect();
    assert_eq!(contacts.len(), 1);
    assert_eq!(contacts[0].0, 1);
    assert!((contacts[0].1 - 0.3).abs() < 1e-6, "{contacts:?}");
    let field = sim.finish();
    assert_eq!((field.get(95, 50), field.get(25, 50)), (-1.0, -0.5));
}
