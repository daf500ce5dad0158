//! Pass 05: cutter radius compensation. Not built yet: until it is, G40, G41
//! and G42 are refused with a clear error rather than ignored, because a
//! program that relies on them would cut the wrong part without them.

use super::{Out, Pass};
use crate::diag::Diagnostic;
use crate::statement::{Kind, Side, Statement};

pub struct CutterComp;

impl Pass for CutterComp {
    fn statement(&mut self, statement: Statement, out: &mut Out) {
        let code = match statement.kind {
            Kind::CutterComp { side: Side::Left, .. } => "G41",
            Kind::CutterComp { side: Side::Right, .. } => "G42",
            Kind::CutterCompCancel => "G40",
            _ => return out.push(statement),
        };
        let diagnostic =
            Diagnostic::error(statement.span, format!("cutter radius compensation ({code}) is not supported yet"))
                .with_help("program the tool centre's path instead (offset the contour by the tool radius)");
        out.error(&statement, diagnostic);
    }
}
