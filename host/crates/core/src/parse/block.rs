//! How the lenient dialect reads a block (a line, or a line up to `;`): as
//! LinuxCNC does. Every word goes to the code of the block that uses it,
//! whatever their order (`G43 M3 Z8.99 H1`: H is G43's, Z a move's in the
//! motion mode in force), and the block's statements come out in LinuxCNC's
//! order of execution: feed, speed, tool, tool change, spindle, coolant,
//! overrides, dwell, plane, units, cutter compensation, tool length,
//! coordinate system, path control, distance mode, retract mode, homing and
//! offsets, motion, and last the stops.

use super::{code_name, code_number, takes_word, Group, Head};
use crate::diag::Diagnostic;
use crate::statement::{Dialect, Value};

/// The axis letters: a block's axis words all go to one code.
const AXES: &str = "XYZABCUVW";
/// Rotary axes: read so that a 3-axis post's constant `A0` can be dropped.
pub(super) const ROTARY: &str = "ABC";

/// The codes of a block and its words, given to their owners and put in the
/// order they run. An error is LinuxCNC's for the same block: two codes of
/// one modal group, or two codes that both use the axis words.
pub(super) fn arrange(block: Vec<Group>, warnings: &mut Vec<Diagnostic>) -> Result<Vec<Group>, Diagnostic> {
    if is_settled(&block) {
        return Ok(block);
    }
    let mut codes = Vec::new();
    let mut words = Vec::new();
    let mut wizards = Vec::new();
    for mut group in block {
        words.append(&mut group.words);
        match group.head {
            Head::Bare => {}
            Head::Wizard { .. } => wizards.push(group),
            // A code written twice (`G0 G90 G0 X0`, as a Fadal post writes
            // it) is read once: LinuxCNC refuses it as two of one group, a
            // Fanuc takes the last of a group, and both mean the same here.
            Head::Code { .. } if codes.iter().any(|code| number(code) == number(&group)) => {}
            Head::Code { .. } => codes.push(group),
        }
    }
    let numbers: Vec<(char, u32)> = codes.iter().map(number).collect();
    check_groups(&codes, &numbers)?;

    let motion = numbers.iter().position(|&code| modal_group(code) == Some(MOTION) && code != ('G', 800));
    let axis_code = numbers.iter().position(|&code| uses_axes(code));
    // G00 or G01 beside G28, G30, G92... (`G00 G91 G28 Z0`, as Fanuc posts
    // write it): the axes are the other code's, and the move's code is the
    // motion mode after it, as a Fanuc reads a block's one-shot code with
    // its modal one. LinuxCNC refuses the block.
    let straight = motion.is_some_and(|m| matches!(numbers[m], ('G', 0 | 10)));
    if let (Some(m), Some(a), false) = (motion, axis_code, straight) {
        if words.iter().any(|(letter, _)| AXES.contains(*letter)) {
            let message = format!(
                "{} and {} both use the axis words of their line",
                code_name(numbers[a].0, f64::from(numbers[a].1) / 10.0),
                code_name(numbers[m].0, f64::from(numbers[m].1) / 10.0)
            );
            return Err(Diagnostic::error(codes[m].span, message).with_help("put them on lines of their own"));
        }
    }
    let g53 = numbers.iter().position(|&code| code == ('G', 530));
    // Fanuc and Haas give a dwell's seconds as X (`G04 X1.5`), where
    // LinuxCNC takes only P: X is the dwell's when nothing else can move.
    let dwell_x = numbers
        .iter()
        .position(|&code| code == ('G', 40))
        .filter(|_| motion.is_none() && axis_code.is_none() && !words.iter().any(|(letter, _)| *letter == 'P'));
    let takes = |i: usize, letter: char| {
        let (code, n) = numbers[i];
        takes_word(code, f64::from(n) / 10.0, letter, Dialect::Lenient)
    };

    let spindle = numbers.iter().position(|&code| matches!(code, ('M', 30 | 40)));
    let mut bare: Option<Group> = None;
    let mut rotary: Option<Group> = None;
    let mut alone = Vec::new();
    for (letter, value) in words {
        let owner = if ROTARY.contains(letter) {
            None
        } else if AXES.contains(letter) {
            axis_code.or(motion).or(dwell_x.filter(|_| letter == 'X')).or(g53)
        } else {
            motion.filter(|&m| takes(m, letter)).or_else(|| (0..codes.len()).find(|&i| takes(i, letter)))
        };
        match owner {
            Some(i) => codes[i].words.push((letter, value)),
            None if ROTARY.contains(letter) => add(&mut rotary, letter, value),
            // A speed or tool with no M03/M04 or M06 to take it is a statement
            // of its own; so are Fadal's fixture offset (E1: G54) and its
            // tool length offset given with a move (H1 Z5.: G43 H1).
            None if matches!(letter, 'S' | 'T' | 'E' | 'H') => {
                // `T11 T12`: which tool is meant? LinuxCNC refuses it too.
                if alone.iter().any(|(_, group): &(u32, Group)| group.words[0].0 == letter) {
                    let message = format!("{letter} appears twice in one block");
                    let help = "a block takes each word once; start a new line for the second";
                    return Err(Diagnostic::error(value.span, message).with_help(help));
                }
                let rank = match letter {
                    'S' => 50,
                    'T' => 60,
                    'H' => 180,
                    _ => 190,
                };
                alone.push((rank, Group { head: Head::Bare, span: value.span, words: vec![(letter, value)] }));
            }
            // Marlin's M3 P: a power in percent, where S would be a speed.
            None if letter == 'P' && spindle.is_some() => {
                let message = format!("P{} on a spindle start is a power (Marlin): it is dropped", value.value);
                let help = "give the spindle speed with S";
                warnings.push(Diagnostic::warning(value.span, message).with_help(help));
            }
            None => add(&mut bare, letter, value),
        }
    }

    let mut ordered: Vec<(u32, Group)> = Vec::new();
    ordered.extend(alone);
    ordered.extend(codes.into_iter().zip(&numbers).map(|(group, &code)| (rank(code), group)));
    ordered.extend(rotary.map(|group| (MOTION_RANK, group)));
    ordered.extend(bare.map(|group| (MOTION_RANK, group)));
    ordered.extend(wizards.into_iter().map(|group| (u32::MAX, group)));
    // Stable: codes of one rank keep the order they were written in.
    ordered.sort_by_key(|(rank, _)| *rank);
    Ok(ordered.into_iter().map(|(_, group)| group).collect())
}

/// Whether a block is one code with only words of its own, which the rules
/// below would leave as they are: most blocks (`G01 X1 Y2 F100`), read
/// without taking them apart.
fn is_settled(block: &[Group]) -> bool {
    let [group] = block else { return false };
    let Head::Code { letter, value } = &group.head else { return false };
    let Some(n) = code_number(value.value) else { return false };
    let code = (*letter, n);
    let takes_axes = (modal_group(code) == Some(MOTION) && code != ('G', 800)) || uses_axes(code) || code == ('G', 530);
    group.words.iter().all(|&(word, _)| match word {
        _ if ROTARY.contains(word) => false,
        _ if AXES.contains(word) => takes_axes,
        _ => takes_word(*letter, value.value, word, Dialect::Lenient),
    })
}

fn add(group: &mut Option<Group>, letter: char, value: Value) {
    let group = group.get_or_insert(Group { head: Head::Bare, span: value.span, words: Vec::new() });
    group.span = group.span.to(value.span);
    group.words.push((letter, value));
}

fn number(group: &Group) -> (char, u32) {
    match &group.head {
        Head::Code { letter, value } => (*letter, code_number(value.value).unwrap_or(u32::MAX)),
        _ => unreachable!("only codes are numbered"),
    }
}

/// Two codes of one modal group cannot share a block (LinuxCNC: "Two g codes
/// used from same modal group"), except G80 beside another motion code, which
/// LinuxCNC takes (Vectric's posts start with `G00G21G17G90G40G49G80`).
fn check_groups(codes: &[Group], numbers: &[(char, u32)]) -> Result<(), Diagnostic> {
    for (i, &code) in numbers.iter().enumerate() {
        let Some(group) = modal_group(code) else { continue };
        let clash = numbers[..i].iter().find(|&&other| {
            modal_group(other) == Some(group) && !(group == MOTION && (other == ('G', 800) || code == ('G', 800)))
        });
        if let Some(&(letter, n)) = clash {
            let first = code_name(letter, f64::from(n) / 10.0);
            let second = code_name(code.0, f64::from(code.1) / 10.0);
            let message = format!("{first} and {second} on one line: they are codes of the same group");
            return Err(Diagnostic::error(codes[i].span, message)
                .with_help(format!("keep one of them, or put {second} on a line of its own")));
        }
    }
    Ok(())
}

const MOTION: u8 = 1;
const NON_MODAL: u8 = 0;

/// LinuxCNC's modal groups, for the codes where two in a block are an error.
fn modal_group((letter, n): (char, u32)) -> Option<u8> {
    let group = match (letter, n) {
        ('G', 0 | 10 | 20 | 30 | 50 | 51 | 52 | 330 | 331 | 380..=385 | 730 | 740 | 760 | 800..=890) => MOTION,
        ('G', 170..=191) => 2,
        ('G', 900 | 910) => 3,
        ('G', 901 | 911) => 4,
        ('G', 930 | 940 | 950) => 5,
        ('G', 200 | 210) => 6,
        ('G', 400 | 410 | 411 | 420 | 421) => 7,
        ('G', 430 | 431 | 432 | 440 | 490) => 8,
        ('G', 980 | 990) => 10,
        ('G', 540..=593 | 1540) => 12,
        ('G', 610 | 611 | 640) => 13,
        ('G', 960 | 970) => 14,
        ('G', 150 | 160) => 15,
        ('G', 40 | 100 | 280 | 281 | 300 | 301 | 520 | 530 | 920..=923) => NON_MODAL,
        ('M', 0 | 10 | 20 | 300 | 600) => 104,
        ('M', 60) => 106,
        ('M', 30 | 40 | 50) => 107,
        ('M', 70 | 80 | 90) => 108,
        ('M', 480 | 490) => 109,
        _ => return None,
    };
    Some(group)
}

/// The codes that take a block's axis words for themselves: G10, G28, G30,
/// G52 and G92 (G53 takes them only when no motion code does).
fn uses_axes(code: (char, u32)) -> bool {
    matches!(code, ('G', 100 | 280 | 300 | 520 | 920))
}

const MOTION_RANK: u32 = 240;

/// Where a code runs in its block: LinuxCNC's order of execution, by tens.
fn rank((letter, n): (char, u32)) -> u32 {
    match (letter, n) {
        ('O', _) => 0,
        ('G', 930 | 940 | 950) => 30,
        ('M', 620..=680) => 70,
        ('M', 60 | 610) => 80,
        ('M', 30 | 40 | 50 | 190) => 90,
        ('G', 960 | 970) => 95,
        ('M', 700..=730) => 100,
        ('M', 70 | 80 | 90) => 110,
        ('M', 480..=530) => 120,
        ('G', 40) => 140,
        ('G', 170..=191) => 150,
        ('G', 200 | 210) => 160,
        ('G', 400..=421) => 170,
        ('G', 430..=490) => 180,
        ('G', 540..=593 | 1540) => 190,
        ('G', 690 | 500 | 501) => 195,
        ('G', 610 | 611 | 640) => 200,
        ('G', 900 | 910 | 901 | 911 | 150 | 160) => 210,
        ('G', 980 | 990) => 220,
        ('G', 100 | 280 | 281 | 300 | 301 | 520 | 920..=923) => 230,
        ('G', 530) => 235,
        ('M', 0 | 10 | 20 | 300 | 600 | 470 | 980 | 990) => 250,
        ('M', _) => 130,
        _ => MOTION_RANK,
    }
}
