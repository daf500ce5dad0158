//! Which tool each description belongs to, in which unit, and the table and
//! stock settled from them.

use super::*;
use crate::config::ToolKind;

fn scanned(text: &str) -> ProgramTools {
    scan(text.as_bytes(), Dialect::Lenient)
}

/// number -> (diameter, unit, line)
fn found(text: &str) -> Vec<(u32, f64, Option<Units>, u32)> {
    scanned(text).tools.iter().map(|(n, e)| (*n, e.described.diameter, e.units, e.line)).collect()
}

#[test]
fn numbered_comments_belong_to_their_tool_and_take_the_programs_unit() {
    // A Fusion 360 header comes before the G21: its lengths are in mm.
    let fusion = "%\n(1001)\n(T1 D=6. CR=0. - ZMIN=-5. - flat end mill)\n(T2 D=3.175 CR=1.5875 - ZMIN=-2. - ball end mill)\nG90 G94 G17\nG21\nT1 M6\nG0 X0 Y0\n";
    assert_eq!(found(fusion), [(1, 6.0, Some(Units::Mm), 3), (2, 3.175, Some(Units::Mm), 4)]);
    // With no G20/G21 anywhere, the machine's unit decides (settled later).
    assert_eq!(found("(T3 D=0.25 CR=0. - ZMIN=-1. - flat end mill)\nG0 X1\n"), [(3, 0.25, None, 1)]);
    // After a G20, in inches; a unit the comment names wins.
    let named = "G20\n(T1 D=0.25 CR=0. - ZMIN=-1. - flat end mill)\n(2 = End Mill {6 mm})\n";
    assert_eq!(found(named), [(1, 0.25, Some(Units::Inch), 2), (2, 6.0, Some(Units::Mm), 3)]);
    // The first description of a tool wins.
    let twice = "(T1 D=6. - flat end mill)\n(T1 D=8. - flat end mill)\n";
    assert_eq!(found(twice), [(1, 6.0, None, 1)]);
}

#[test]
fn unnumbered_comments_belong_to_the_next_tool_change_or_the_loaded_tool() {
    // Carbide Create: CutViewer's TOOL/MILL before each M6Tn.
    let carbide = "(STOCK/BLOCK,100.00, 100.00, 1.00,0.00, 0.00, 1.00)\nG90\nG21\nG53G0Z-5.000\nM05\n\
                   (TOOL/MILL,3.17, 0.00, 0.00, 0.00)\nM6T102\nM03S18000\nG0X0.000Y0.000\nG1Z-0.762F381.0\n\
                   M05\nG53G0Z-5.000\n(TOOL/MILL,0.03, 0.00, 10.00, 45.00)\nM6T390\nG0X1Y1\n";
    let scan = scanned(carbide);
    let tools: Vec<(u32, ToolKind, u32)> = scan.tools.iter().map(|(n, e)| (*n, e.described.kind, e.line)).collect();
    assert_eq!(tools, [(102, ToolKind::Endmill, 6), (390, ToolKind::Drill, 13)]);
    let (block, units, line) = scan.stock.unwrap();
    assert_eq!((block.size, block.origin, units, line), ([100.0, 100.0, 1.0], [0.0, 0.0, 1.0], Some(Units::Mm), 1));

    // Vectric names the tool after the change: a move comes first, so it is the loaded tool's.
    let vectric =
        "N100G00G20G17G90G40G49G80\nN120T5M06\nN130 (Tool: End Mill {0.2500 inch} UpDown)\nN140G00G43Z2.0000H5\n";
    assert_eq!(found(vectric), [(5, 0.25, Some(Units::Inch), 3)]);

    // viaconstructor: no tool changes at all, so tool 1.
    assert_eq!(found("G21\n(Tool-Diameter: 4.0mm)\nG0 Z5\n"), [(1, 4.0, Some(Units::Mm), 2)]);

    // "T2" selects, but only M06 loads: the move after a bare T2 is still tool 1's.
    assert_eq!(found("T2\n(Tool: 1/4 in End Mill)\nG0 X1\nM06\n"), [(1, 0.25, Some(Units::Inch), 2)]);
    assert_eq!(found("T2\nM06\n(Tool: 1/4 in End Mill)\nG0 X1\n"), [(2, 0.25, Some(Units::Inch), 3)]);
}

#[test]
fn moves_after_a_waiting_description_and_comments_over_lines_are_read() {
    // The move right after an unnumbered tool is the loaded tool's, though no G code is on its line.
    assert_eq!(found("(Tool: 1/4 in End Mill)\nX1 Y1\nT2 M6\nX2\n"), [(1, 0.25, Some(Units::Inch), 1)]);
    // A comment over three lines, its middle line bare.
    assert_eq!(found("G20\n(Tool:\n1/4 in End Mill\n)\nX1\n"), [(1, 0.25, Some(Units::Inch), 2)]);
    // Line numbers count every line, the moves passed over too; CR and CRLF end lines as in the lexer.
    assert_eq!(found("G20\r\nX1\rX2\nX3\n(T4 D=0.5 - drill)\n"), [(4, 0.5, Some(Units::Inch), 5)]);
}

#[test]
fn estlcams_list_names_the_first_tool() {
    // As Estlcam writes it (lagun-linuxcnc's crankyanker_aug8.ngc): tool changes are M00 pauses.
    let estlcam = "(Project crankyanker_aug8)\n(Created by Estlcam version 11 build 11.245)\n\n(Required tools:)\n\
                   (End mill 3/8)\n(End mill 1/8)\n\nG90\nM03 S12000\nG00 Z0.19685\n\
                   M00 (Change tool: End mill 1/8)\nG00 Z1\n";
    assert_eq!(found(estlcam), [(1, 0.375, Some(Units::Inch), 5)]);
}

#[test]
fn a_million_comments_take_bounded_memory() {
    let mut text = String::new();
    for n in 0..(MAX_DESCRIBED as u32 + 50) {
        text.push_str(&format!("(T{n} D=1. - flat end mill)\n(Tool: {n} mm end mill)\n"));
    }
    let scan = scanned(&text);
    assert_eq!(scan.tools.len(), MAX_DESCRIBED);
}

fn mm_config() -> Config {
    Config::from_toml("units = \"mm\"\n").unwrap()
}

#[test]
fn without_a_tool_table_the_program_describes_the_tools_and_tool_1_defaults() {
    // Tools in inches, on a mm machine, and no tool 1.
    let program = scanned("G20\n(T2 D=0.25 CR=0. - ZMIN=-1. - flat end mill)\n(T3 D=0.5 CR=0. TAPER=118deg - drill)\n");
    let mut config = mm_config();
    settle(&mut config, None, None, &program);
    let table: Vec<(u32, ToolKind, f64)> = config.tools.iter().map(|t| (t.number, t.kind, t.diameter)).collect();
    assert_eq!(table.len(), 3);
    assert_eq!((table[0].0, table[0].1), (2, ToolKind::Endmill));
    assert!((table[0].2 - 6.35).abs() < 1e-9);
    assert!((table[1].2 - 12.7).abs() < 1e-9);
    // The default tool 1 is a quarter inch in a mm machine too.
    assert_eq!(table[2].0, 1);
    assert!((table[2].2 - 6.35).abs() < 1e-9, "{}", table[2].2);
    assert_eq!(config.tool_source(2), Some(&ToolSource::Comment { line: 2 }));
    assert_eq!(config.tool_source(1), Some(&ToolSource::Default));
}

#[test]
fn the_config_file_wins_then_the_project_then_the_comments() {
    let program = scanned("(T1 D=6. - flat end mill)\n(T2 D=3. - flat end mill)\n(STOCK/BLOCK,10,10,1,0,0,1)\n");

    let mut config =
        Config::from_toml("units = \"mm\"\n[[tools]]\nnumber = 1\nkind = \"drill\"\ndiameter = 5\n").unwrap();
    settle(&mut config, Some("ger.toml"), None, &program);
    assert_eq!(config.tools.len(), 1);
    assert_eq!(config.tool(1).unwrap().kind, ToolKind::Drill);
    assert_eq!(config.tool_source(1), Some(&ToolSource::Config { file: "ger.toml".into() }));
    // ...but the stock the file leaves out comes from the program.
    assert_eq!((config.stock.size, config.stock.origin), (Some([10.0, 10.0, 1.0]), Some([0.0, 0.0, 1.0])));

    let project = camotics::parse(
        r#"{ "tools": { "1": { "units": "imperial", "shape": "ballnose", "diameter": 0.125, "length": 1 } },
             "workpiece": { "automatic": false, "bounds": { "min": [-2, -1, -32], "max": [92, 89, 0] } } }"#,
    )
    .unwrap();
    let mut config = mm_config();
    settle(&mut config, None, Some(("part.camotics", &project)), &program);
    let one = config.tool(1).unwrap();
    assert_eq!((one.kind, one.diameter), (ToolKind::Ballmill, 3.175));
    assert_eq!(config.tool_source(1), Some(&ToolSource::Camotics { file: "part.camotics".into() }));
    assert_eq!(config.tool(2).unwrap().diameter, 3.0);
    assert_eq!(config.tool_source(2), Some(&ToolSource::Comment { line: 2 }));
    // The project's workpiece: 94 x 90 x 32 mm, program zero 2, 1 and 32 mm in from its lowest corner.
    assert_eq!((config.stock.size, config.stock.origin), (Some([94.0, 90.0, 32.0]), Some([2.0, 1.0, 32.0])));

    // In an inch machine the project's millimetres are converted.
    let mut config = Config::default();
    settle(&mut config, None, Some(("part.camotics", &project)), &program);
    assert!((config.tool(1).unwrap().diameter - 0.125).abs() < 1e-12);
    let size = config.stock.size.unwrap();
    assert!((size[0] - 94.0 / 25.4).abs() < 1e-12);

    // [stock] in the file wins over everything.
    let mut config = Config::from_toml("units = \"mm\"\n[stock]\nmargin = 1\n").unwrap();
    settle(&mut config, None, Some(("part.camotics", &project)), &program);
    assert_eq!((config.stock.size, config.stock.margin), (None, Some(1.0)));
}

#[test]
fn nonsense_descriptions_are_not_tools() {
    // A zero diameter would cut nothing; the default tool 1 stands in.
    let program = scanned("(T1 D=0 - flat end mill)\n(STOCK/BLOCK,0,10,1,0,0,1)\n");
    let mut config = mm_config();
    settle(&mut config, None, None, &program);
    assert_eq!(config.tool_source(1), Some(&ToolSource::Default));
    assert_eq!(config.stock, StockConfig::default());
}

#[test]
fn descriptions_past_what_ger_toml_allows_are_not_tools() {
    // A 5 m endmill and a 200 m block: past config::Bounds (1 m tools, 100 m lengths).
    let program = scanned("G21\n(T1 D=5000. CR=0. - ZMIN=-1. - flat end mill)\n(STOCK/BLOCK,200000,10,1,0,0,1)\n");
    let mut config = mm_config();
    settle(&mut config, None, None, &program);
    assert_eq!(config.tool_source(1), Some(&ToolSource::Default));
    assert_eq!(config.stock, StockConfig::default());
    // The same in inches is 127 mm and 5.08 m: a face mill and a gantry's bed.
    let program = scanned("G20\n(T1 D=5. CR=0. - ZMIN=-1. - face mill)\n(STOCK/BLOCK,200,10,1,0,0,1)\n");
    let mut config = mm_config();
    settle(&mut config, None, None, &program);
    assert_eq!(config.tool_source(1), Some(&ToolSource::Comment { line: 2 }));
    assert_eq!(config.stock.size, Some([5080.0, 254.0, 25.4]));
}
