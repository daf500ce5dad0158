//! Each rule on lines as the posts write them (most from the shared corpus
//! or from the posts' own templates), and on lines it must leave alone.

use super::*;

fn tool(comment: &str) -> Described {
    match read(comment) {
        Some(Found::Tool(described)) => described,
        other => panic!("{comment}: {other:?}"),
    }
}

/// (number, kind, diameter, tip angle, unit named)
fn summary(d: &Described) -> (Option<u32>, ToolKind, f64, Option<f64>, Option<Units>) {
    (d.number, d.kind, d.diameter, d.tip_angle, d.units)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

#[test]
fn fusion_tool_comments() {
    use ToolKind::*;
    for (comment, expected) in [
        ("T1 D=6. CR=0. - ZMIN=-5. - flat end mill", (Some(1), Endmill, 6.0, None, None)),
        // The corpus's own spacing and capitals.
        ("T1  D=2.7 CR=0 - ZMIN=-13.3 - flat end mill", (Some(1), Endmill, 2.7, None, None)),
        ("T2 D=0.3125 CR=0. - ZMIN=-0.455 - FLAT END MILL", (Some(2), Endmill, 0.3125, None, None)),
        // CR = D/2 is a ball, whatever the type says.
        ("T2 D=3.175 CR=1.5875 - ZMIN=-2. - ball end mill", (Some(2), Ballmill, 3.175, None, None)),
        ("T1 D=0.5 CR=0.25 - ZMIN=-0.6275 - BALL END MILL", (Some(1), Ballmill, 0.5, None, None)),
        ("T5 D=3.175 CR=3.175 - ZMIN=-12.7 - RADIUS MILL", (Some(5), Ballmill, 3.175, None, None)),
        // A bull nose is simulated flat.
        ("T4 D=10. CR=1. - ZMIN=-3. - bull nose end mill", (Some(4), Endmill, 10.0, None, None)),
        // Drills and spot drills give their point's angle...
        ("T1 D=0.236 CR=0. TAPER=118DEG - ZMIN=-0.125 - DRILL", (Some(1), Drill, 0.236, Some(118.0), None)),
        ("T4 D=5. CR=0. TAPER=118deg - ZMIN=-10. - drill", (Some(4), Drill, 5.0, Some(118.0), None)),
        (
            "T1  D=4. CR=0. TAPER=90deg - ZMIN=-1. - spot drill - 4mm Spot Drill",
            (Some(1), CenterDrill, 4.0, Some(90.0), None),
        ),
        // ...chamfer mills their taper from the axis: 45 degrees is a 90-degree point.
        ("T3 D=12.7  CR=0. TAPER=45DEG - ZMIN=18.542 - CHAMFER MILL", (Some(3), Drill, 12.7, Some(90.0), None)),
        ("T34  D=6 CR=0 TAPER=118deg - ZMIN=-27.203 - drill", (Some(34), Drill, 6.0, Some(118.0), None)),
        ("T1  D=40 CR=0 - ZMIN=0 - face mill", (Some(1), Endmill, 40.0, None, None)),
    ] {
        assert_eq!(summary(&tool(comment)), expected, "{comment}");
    }
    // A chamfer mill whose taper is 90 from the axis is not a point: left to the default cone.
    assert_eq!(tool("T3 D=6. CR=0. TAPER=90deg - ZMIN=-1. - chamfer mill").tip_angle, Some(90.0));
}

#[test]
fn mastercam_tool_comments() {
    use ToolKind::*;
    for (comment, expected) in [
        (" 1/16 FLAT ENDMILL TOOL - 1 DIA. OFF. - 1 LEN. - 1 DIA. - .0625", (Some(1), Endmill, 0.0625, None, None)),
        (
            " TOOL - 6 2\"  MITSUBISIHI FACE MILL    DIA. OFF. - 6  LEN. - 6  DIA. - 2. ",
            (Some(6), Endmill, 2.0, None, None),
        ),
        (
            " 1/8 X 900 CHAMFER MILL TOOL - 14 DIA. OFF. - 14 LEN. - 14 TOOL DIA. - .125 ",
            (Some(14), Drill, 0.125, Some(90.0), None),
        ),
        // The table rows of newer posts: the D field is an offset register.
        (" T212 |    3. FLAT ENDMILL | H0 ", (Some(212), Endmill, 3.0, None, None)),
        ("T1 | 10. FLAT ENDMILL | H1 | D10.", (Some(1), Endmill, 10.0, None, None)),
        ("T2 | 6. BALL ENDMILL | H2 | D6.", (Some(2), Ballmill, 6.0, None, None)),
        (" T1 | 1/4 FLAT ENDMILL | H1 | D1 | TOOL DIA. - .25 ", (Some(1), Endmill, 0.25, None, None)),
    ] {
        assert_eq!(summary(&tool(comment)), expected, "{comment}");
    }
}

#[test]
fn numbered_tool_lists() {
    use ToolKind::*;
    use Units::*;
    for (comment, expected) in [
        // Vectric's [TOOLS_USED].
        ("1 = End Mill {6 mm}", (Some(1), Endmill, 6.0, None, Some(Mm))),
        ("5 = End Mill {0.2500 inch} UpDown", (Some(5), Endmill, 0.25, None, Some(Inch))),
        ("T2 = End Mill {0.5 inches}", (Some(2), Endmill, 0.5, None, Some(Inch))),
        ("3 = V-Bit {60 deg 0.5 inch}", (Some(3), Drill, 0.5, Some(60.0), Some(Inch))),
        ("4 = Ball Nose {3 mm}", (Some(4), Ballmill, 3.0, None, Some(Mm))),
        // Headers machinists write (the corpus's Haas programs): part numbers are not sizes.
        ("T01 = 1/2\"  END MILL    03-0086", (Some(1), Endmill, 0.5, None, Some(Inch))),
        ("T22 = .238\" B DRILL     03-0259, 135 Point Angle", (Some(22), Drill, 0.238, Some(135.0), Some(Inch))),
        ("T07 = 1/4\"  DRILL       03-0094, 140 Point Angle", (Some(7), Drill, 0.25, Some(140.0), Some(Inch))),
        ("T05 = 1/4\"  SPOT DRILL  03-2222", (Some(5), CenterDrill, 0.25, None, Some(Inch))),
        ("T10 = 2.0\" FACE MILL 01-0001", (Some(10), Endmill, 2.0, None, Some(Inch))),
        (
            "T01 = .5\" ENDMILL 3 FLUTES SPEED 10000RPM FEED 108.0IPM PRODUCT 03-0086",
            (Some(1), Endmill, 0.5, None, Some(Inch)),
        ),
        ("T1 - .5 END MILL", (Some(1), Endmill, 0.5, None, None)),
        ("T10 - 2. FACE MILL", (Some(10), Endmill, 2.0, None, None)),
        ("TOOL 1 = 1IN FACE MILL", (Some(1), Endmill, 1.0, None, Some(Inch))),
        ("T1 = 1-1/2\" FACE MILL", (Some(1), Endmill, 1.5, None, Some(Inch))),
        // CamBam: the size alone.
        (" T1 : 6.0 ", (Some(1), Endmill, 6.0, None, None)),
    ] {
        assert_eq!(summary(&tool(comment)), expected, "{comment}");
    }
}

#[test]
fn tools_named_without_a_number() {
    use ToolKind::*;
    use Units::*;
    for (comment, expected) in [
        // Vectric after each tool change, and inside a toolpath's comment.
        ("Tool: End Mill {0.2500 inch} UpDown", (None, Endmill, 0.25, None, Some(Inch))),
        ("Toolpath: Pocket 1 Tool: Ball Nose {1/8 inch}", (None, Ballmill, 0.125, None, Some(Inch))),
        // FreeCAD's tool controller, Estlcam's change, a hand-written LinuxCNC header.
        ("TC: 5mm Endmill", (None, Endmill, 5.0, None, Some(Mm))),
        ("Change tool: End mill 1/8", (None, Endmill, 0.125, None, Some(Inch))),
        (" Tool: 1/4 In Endmill, 2 Flutes, HSS", (None, Endmill, 0.25, None, Some(Inch))),
        ("Tool: 3/8 in Carbide End Mill", (None, Endmill, 0.375, None, Some(Inch))),
        // Measured rather than named (viaconstructor's, and the generic forms).
        ("Tool-Diameter: 4.0mm", (None, Endmill, 4.0, None, Some(Mm))),
        ("Tool Diameter: 6.35", (None, Endmill, 6.35, None, None)),
        ("TOOL DIA. - .25", (None, Endmill, 0.25, None, None)),
    ] {
        assert_eq!(summary(&tool(comment)), expected, "{comment}");
    }
    // Estlcam lists its tools' names after "Required tools:".
    assert_eq!(read("Required tools:"), Some(Found::ToolList));
    let listed = listed_name("End mill 3/8").unwrap();
    assert_eq!(summary(&listed), (None, Endmill, 0.375, None, Some(Inch)));
    assert_eq!(listed_name("End mill 3 mm").map(|d| (d.diameter, d.units)), Some((3.0, Some(Mm))));
}

#[test]
fn cutviewer_statements() {
    use ToolKind::*;
    // Carbide Create: a 1/8" endmill, and a 90-degree V-bit 10 mm tall from a 0.03 mm tip.
    let endmill = tool("TOOL/MILL,3.17, 0.00, 0.00, 0.00");
    assert_eq!((summary(&endmill), endmill.flute_length), ((None, Endmill, 3.17, None, None), None));
    let vbit = tool("TOOL/MILL,0.03, 0.00, 10.00, 45.00");
    assert_eq!((vbit.kind, vbit.tip_angle), (Drill, Some(90.0)));
    assert!(close(vbit.diameter, 20.03), "{}", vbit.diameter);
    let ball = tool("TOOL/MILL,6.35, 3.175, 19.05, 0.00");
    assert_eq!((ball.kind, ball.flute_length), (Ballmill, Some(19.05)));
    let bull = tool("TOOL/MILL, 10, 1, 25, 0");
    assert_eq!(bull.kind, Endmill);
    let drill = tool("TOOL/DRILL, 5, 118, 40");
    assert_eq!((summary(&drill), drill.flute_length), ((None, Drill, 5.0, Some(118.0), None), Some(40.0)));
    assert_eq!(summary(&tool("TOOL/CHAMFER,12,45,20,5")), (None, Drill, 12.0, Some(90.0), None));
    assert_eq!(summary(&tool("TOOL/CDRILL,2,118,3,5,60,10")), (None, CenterDrill, 5.0, Some(60.0), None));
    assert_eq!(
        read("STOCK/BLOCK,100.00, 100.00, 1.00,0.00, 0.00, 1.00"),
        Some(Found::Stock(Block { size: [100.0, 100.0, 1.0], origin: [0.0, 0.0, 1.0] }))
    );
}

#[test]
fn comments_that_are_not_tools_are_left_alone() {
    for comment in [
        "2D Pocket1",
        "DRILL HOLES",
        "Drill1",
        "T22 - B DRILL",
        "T1 = TOOL CHANGE",
        "T1 - ROUGHING 2 PASSES",
        "End mill 1/4",
        "TC: Default Tool",
        "begin toolchange",
        "MSG, Change tool bit",
        "When using Fusion 360 for Personal Use, the feedrate of",
        "Toolpath:- Pocket 1",
        "T1 D=abc - flat end mill",
        "Tool-Diameter: none",
        "#24xx: #xx tool diameter",
        "STOCK/BLOCK,100,100",
        "TOOL/MILL,big",
        "G20 (units in inches)",
    ] {
        assert_eq!(read(comment), None, "{comment}");
    }
}

#[test]
fn nothing_breaks_on_odd_text() {
    for comment in
        ["", "T", "T99999999999999 D=1 - drill", "1/0 END MILL", "TOOL - ", "|", "T1 |", "Tool:", "Ø6 Fräser"]
    {
        let _ = read(comment);
    }
    // A diameter too large to be a number is not a tool.
    assert_eq!(read(&format!("T1 D={} - flat end mill", "9".repeat(400))), None);
}
