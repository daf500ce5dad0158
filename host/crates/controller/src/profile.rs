//! The targets as data: one [`Profile`] per controller, saying what its
//! lines must look like. A rule is a field; `writer.rs` applies them. To add
//! a controller, add a profile and its name in `ger_core::config::TargetName`.

use ger_core::config::TargetName;

/// What a controller takes, field by field; `None` or `false` is "as ger
/// writes it".
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    pub name: TargetName,
    /// Which controller the notes name: "GRBL".
    pub label: &'static str,
    /// `%` alone on the first and last lines (the tape framing a Fanuc wants).
    pub percent_framing: bool,
    /// An `O` number line after the first `%`: a Fanuc stores programs by it.
    pub program_number: bool,
    /// Lines written before the first move, after the modes (G21 G90 G17).
    pub setup: &'static [&'static str],
    /// The largest N word it reads; a line past it is written without one.
    pub max_line_number: Option<u32>,
    /// How many characters a line may have, spaces and comments aside (its line buffer).
    pub max_line_length: Option<usize>,
    /// Numbers without trailing zeros and with at most this many digits.
    pub max_digits: Option<usize>,
    /// What a tool change (M06) becomes.
    pub tool_change: ToolChange,
    /// What `G43 Hn` / `G44 Hn` become.
    pub tool_length: ToolLength,
    /// M07 needs `[target] mist = true` (a build option of the controller).
    pub mist_optional: bool,
    /// M codes it does not have (by ger's numbering, M40 = 40): left out with a note.
    pub missing_m_codes: &'static [u32],
    /// Codes ger passes through from the program (`M62 P1`, `M100`) are left out with a note.
    pub no_pass_through: bool,
    /// The dwell's word: `P` seconds, or Fanuc's `X` seconds (its `P` is milliseconds).
    pub dwell_word: char,
    /// It reads LinuxCNC's `G10 L1` (a tool table entry written by the
    /// program); elsewhere the line is left out with a note.
    pub tool_table_write: bool,
    /// Comments: which characters are kept (others are left out), and
    /// whether they are upper-cased first.
    pub comments: Comments,
    /// The controller refuses an arc whose end is off its circle by more than
    /// this (GRBL's end-radius check); such an arc is written as lines.
    pub arc_check: Option<ArcCheck>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolChange {
    /// `M06 Tn`, as ger writes it.
    M6,
    /// No M06: the spindle stops and the program pauses (M00) with the tool
    /// named in a comment, unless `[target] tool_change` gives the block.
    Pause,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolLength {
    /// `G43 Hn`, from the controller's tool table.
    Register,
    /// `G43.1 Z<length>` from `[target] tool_lengths` (GRBL has no tool table).
    Dynamic,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Comments {
    /// Any printable ASCII but `(` and `)`.
    Ascii,
    /// Printable ASCII but GRBL's realtime commands `!` `~` `?` (acted on
    /// wherever they come, comments too).
    AsciiWithoutRealtime,
    /// Upper case, letters, digits, space and `. , = _ -` (anything else a
    /// space): what a Fanuc takes in a comment on any of its controls.
    FanucUpper,
}

/// GRBL's rule: an arc is refused when the distance from its centre to its
/// end differs from the radius (the distance to its start) by more than
/// `mm` AND by more than `fraction` of the radius, or by more than `most_mm`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcCheck {
    pub mm: f64,
    pub fraction: f64,
    pub most_mm: f64,
}

pub const GENERIC: Profile = Profile {
    name: TargetName::Generic,
    label: "ger",
    percent_framing: false,
    program_number: false,
    setup: &[],
    max_line_number: None,
    max_line_length: None,
    max_digits: None,
    tool_change: ToolChange::M6,
    tool_length: ToolLength::Register,
    mist_optional: false,
    missing_m_codes: &[],
    no_pass_through: false,
    dwell_word: 'P',
    tool_table_write: true,
    comments: Comments::Ascii,
    arc_check: None,
};

/// GRBL 1.1 (checked with its own parser, `../shared/peers/grbl/bin/gvalidate`).
pub const GRBL: Profile = Profile {
    name: TargetName::Grbl,
    label: "GRBL",
    // N10000000 is read, N10000001 is error:27.
    max_line_number: Some(10_000_000),
    // An 80-byte line buffer with its terminator: 80 characters is error:11.
    max_line_length: Some(79),
    // read_float keeps 8 digits and drops the rest.
    max_digits: Some(8),
    tool_change: ToolChange::Pause,
    tool_length: ToolLength::Dynamic,
    mist_optional: true,
    // M40, M41 (spindle range) and M48, M49 (overrides) are error:20.
    missing_m_codes: &[40, 41, 48, 49],
    no_pass_through: true,
    // No tool table at all.
    tool_table_write: false,
    comments: Comments::AsciiWithoutRealtime,
    arc_check: Some(ArcCheck { mm: 0.005, fraction: 0.001, most_mm: 0.5 }),
    ..GENERIC
};

/// LinuxCNC 2.9: ger's output is its dialect (rs274 reads N100000 too),
/// but it has no spindle ranges ("Unknown m code used: M40").
pub const LINUXCNC: Profile =
    Profile { name: TargetName::Linuxcnc, label: "LinuxCNC", missing_m_codes: &[40, 41], ..GENERIC };

/// A Fanuc 0i/30i-style control (Haas reads it too).
pub const FANUC: Profile = Profile {
    name: TargetName::Fanuc,
    label: "Fanuc",
    percent_framing: true,
    program_number: true,
    // Sequence numbers have five digits.
    max_line_number: Some(99_999),
    dwell_word: 'X',
    // Its offsets are written with G10 L10-L13 into H and D registers, not by tool.
    tool_table_write: false,
    comments: Comments::FanucUpper,
    ..GENERIC
};

/// Mach3: I and J may be set absolute in its config, so the output says G91.1.
/// Its G10 L1 is not known to take LinuxCNC's words, so the line is left out.
pub const MACH3: Profile = Profile {
    name: TargetName::Mach3,
    label: "Mach3",
    setup: &["G91.1"],
    missing_m_codes: &[40, 41],
    tool_table_write: false,
    ..GENERIC
};

/// The profile of a target.
pub fn of(name: TargetName) -> &'static Profile {
    match name {
        TargetName::Generic => &GENERIC,
        TargetName::Grbl => &GRBL,
        TargetName::Linuxcnc => &LINUXCNC,
        TargetName::Fanuc => &FANUC,
        TargetName::Mach3 => &MACH3,
    }
}
