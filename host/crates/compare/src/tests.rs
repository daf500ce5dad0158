//! Designs read from STL text written here, and their top surfaces against geometry.

use super::*;
use ger_sim::Stock;

/// An ASCII STL of `triangles`.
fn ascii(triangles: &[[[f64; 3]; 3]]) -> String {
    let mut text = String::from("solid test\n");
    for t in triangles {
        text.push_str("facet normal 0 0 0\nouter loop\n");
        for v in t {
            text.push_str(&format!("vertex {} {} {}\n", v[0], v[1], v[2]));
        }
        text.push_str("endloop\nendfacet\n");
    }
    text + "endsolid test\n"
}

/// A tetrahedron: three faces up and one down, under the apex (1, 1, 3) over the base (0..4, 0..4, 0).
fn tetrahedron() -> Vec<[[f64; 3]; 3]> {
    let (a, b, c, d) = ([0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0], [1.0, 1.0, 3.0]);
    vec![[a, c, b], [a, b, d], [b, c, d], [c, a, d]]
}

#[test]
fn a_closed_mesh_is_read_and_its_top_surface_is_its_highest_point_over_each_cell() {
    let design = Design::read(&mut std::io::Cursor::new(ascii(&tetrahedron()))).unwrap();
    assert_eq!(design.bounds(), (Point::new(0.0, 0.0, 0.0), Point::new(4.0, 4.0, 3.0)));
    let stock = Stock { min: Point::new(0.0, 0.0, -1.0), max: Point::new(4.0, 4.0, 3.0) };
    let field = HeightField::new(stock, 0.5).unwrap();
    let top = design.top_surface(&field);
    // The upper faces are planes through two base corners and the apex (1, 1, 3): over the y = 0
    // edge z = 3 y, over x = 0 z = 3 x, over x + y = 4 z = 3 (4 - x - y) / 2; the top, a convex
    // solid's, is the least of the three (0 on the base's edge, which the cells on it share).
    for j in 0..field.ny {
        for i in 0..field.nx {
            let [x, y] = field.centre(i, j);
            let expected = if x + y <= 4.0 { Some((3.0 * x).min(3.0 * y).min(1.5 * (4.0 - x - y))) } else { None };
            let got = top[j * field.nx + i];
            match (got, expected) {
                (Some(g), Some(e)) => assert!((g - e).abs() < 1e-9, "({x}, {y}): {g} vs {e}"),
                (g, e) => assert_eq!(g, e, "({x}, {y})"),
            }
        }
    }
}

#[test]
fn a_mesh_that_is_not_a_solid_is_refused_saying_why() {
    let mut open = tetrahedron();
    open.pop();
    let err = Design::read(&mut std::io::Cursor::new(ascii(&open))).unwrap_err();
    assert!(matches!(err, DesignError::Open(_)), "{err}");
    assert!(err.to_string().contains("not a closed surface"), "{err}");
    let err = Design::read(&mut std::io::Cursor::new(b"solid x\nfacet normal\n".to_vec())).unwrap_err();
    assert!(matches!(err, DesignError::Unreadable(_)), "{err}");
    assert!(matches!(Design::read(&mut std::io::Cursor::new(ascii(&[]))).unwrap_err(), DesignError::Empty));
}

#[test]
fn placing_scales_then_shifts() {
    let mut design = Design::read(&mut std::io::Cursor::new(ascii(&tetrahedron()))).unwrap();
    design.place(25.4, Point::new(1.0, 2.0, 3.0));
    let (lo, hi) = design.bounds();
    assert!(lo.abs_diff_eq(Point::new(1.0, 2.0, 3.0), 1e-9) && hi.abs_diff_eq(Point::new(102.6, 103.6, 79.2), 1e-9));
}

#[test]
fn a_long_thin_triangle_across_the_grid_covers_the_cells_under_it_alone() {
    // From (0, 0) to (20, 20) and (20, 19): between y = x and y = 0.95 x, up to x = 20, level at z 2.
    // Its box is the whole 20 x 20 grid; it covers a sliver of it.
    let design = Design {
        triangles: vec![[Point::new(0.0, 0.0, 2.0), Point::new(20.0, 19.0, 2.0), Point::new(20.0, 20.0, 2.0)]],
    };
    let stock = Stock { min: Point::new(0.0, 0.0, 0.0), max: Point::new(20.0, 20.0, 3.0) };
    let field = HeightField::new(stock, 0.1).unwrap();
    let top = design.top_surface(&field);
    let mut covered = 0;
    for j in 0..field.ny {
        for i in 0..field.nx {
            let [x, y] = field.centre(i, j);
            let inside = y <= x && y >= 0.95 * x && x <= 20.0;
            let got = top[j * field.nx + i];
            assert_eq!(got.is_some(), inside, "({x}, {y})");
            assert!(got.is_none_or(|z| (z - 2.0).abs() < 1e-9), "({x}, {y}): {got:?}");
            covered += usize::from(inside);
        }
    }
    // Its 10 mm² in cells of 0.01 mm², and the 200 centres on its edge along y = x.
    assert_eq!(covered, 1100);
}
