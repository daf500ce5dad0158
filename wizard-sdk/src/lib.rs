//! Write a ger wizard in Rust.
//!
//! A wizard is a type that implements [`Wizard`], exported with
//! [`export_wizard!`]; build it with `ger wizard build NAME`. The WIT
//! contract (`wit/wizard.wit`) and wit-bindgen stay out of sight: a wizard
//! sees plain Rust types ([`State`], [`Arg`], [`Statement`]) and builds its
//! output with [`g0`], [`g1`], [`g2`], [`g3`], [`g`], [`m`], [`comment`] and
//! [`call`]; [`entry`] takes a cutter down into material by a ramp or a
//! helix instead of a plunge, [`contour`] follows a closed path of lines and
//! arcs at heights that change along it (ramps along the path, holding
//! tabs) and joins it by tangent lead-in and lead-out arcs, and [`holes`]
//! drills as G81, G83 or G73 would.
//!
//! ```no_run
//! use ger_wizard_sdk::*;
//!
//! struct Square;
//!
//! impl Wizard for Square {
//!     fn describe() -> Description {
//!         Description::new("Square", "Mills a square outline", "Square SIDE")
//!             .param("SIDE", "side length")
//!     }
//!
//!     fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String> {
//!         let side = args.positive(0)?;
//!         let [x, y, _] = state.position;
//!         Ok(vec![
//!             g1().x(x + side).into(),
//!             g1().y(y + side).into(),
//!             g1().x(x).into(),
//!             g1().y(y).into(),
//!         ])
//!     }
//! }
//!
//! export_wizard!(Square);
//! ```

mod args;
mod block;
pub mod contour;
pub mod entry;
pub mod holes;
mod state;

pub use args::{Arg, Args};
pub use block::{call, comment, g, g0, g1, g2, g3, m, text, Block, Call, Statement};
pub use state::{Distance, Plane, Spindle, State, Stock, Tool, ToolKind, Units};

/// The generated bindings; used by [`export_wizard!`], not by wizards.
#[doc(hidden)]
pub mod __bindings {
    wit_bindgen::generate!({
        path: "../wit",
        world: "ger:wizard/wizard",
        pub_export_macro: true,
        default_bindings_module: "ger_wizard_sdk::__bindings",
    });
}

use __bindings::ger::wizard::{host, types as wit};

/// A wizard: what it is, and what a call of it becomes.
pub trait Wizard {
    /// Name, summary, usage and parameters, for `ger wizard list` and for
    /// the errors [`Args`] reports.
    fn describe() -> Description;

    /// The statements that replace one call, or a message saying why there
    /// are none (ger shows it at the call).
    fn expand(args: &Args, state: &State) -> Result<Vec<Statement>, String>;
}

/// What a wizard says about itself.
#[derive(Clone, Debug, PartialEq)]
pub struct Description {
    pub name: String,
    pub summary: String,
    pub usage: String,
    /// (name, description, optional)
    pub params: Vec<Param>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub name: String,
    pub description: String,
    pub optional: bool,
}

impl Description {
    pub fn new(name: &str, summary: &str, usage: &str) -> Description {
        Description { name: name.into(), summary: summary.into(), usage: usage.into(), params: Vec::new() }
    }

    /// A required parameter, in call order.
    pub fn param(mut self, name: &str, description: &str) -> Description {
        self.params.push(Param { name: name.into(), description: description.into(), optional: false });
        self
    }

    /// An optional parameter; optional ones come after the required ones.
    pub fn optional(mut self, name: &str, description: &str) -> Description {
        self.params.push(Param { name: name.into(), description: description.into(), optional: true });
        self
    }
}

/// Logs a line; ger shows the log with the diagnostic if the call fails.
pub fn log(message: &str) {
    host::log(message);
}

/// Looks a tool up in the machine's tool table, in the program's units.
pub fn tool(number: u32) -> Option<Tool> {
    host::find_tool(number).map(Tool::from)
}

/// The machine's whole tool table, in the program's units, by number.
pub fn tools() -> Vec<Tool> {
    host::tools().into_iter().map(Tool::from).collect()
}

/// The stock block at the call, or `None` when ger finds it only from what
/// the program cuts.
pub fn stock() -> Option<Stock> {
    host::stock().map(Stock::from)
}

/// The machine's unit, whatever G20/G21 the program is in.
pub fn machine_units() -> Units {
    host::machine_units().into()
}

/// A warning at the call (`ger check --deny warnings` fails on it); the
/// call's statements still run. For what is allowed but unwise: a feed
/// the tool may not take, a depth past its flutes.
pub fn warn(message: &str) {
    host::warn(message);
}

/// Exports `$wizard` (a type implementing [`Wizard`]) as the component's
/// `describe` and `expand`. Use it once, at the crate root.
#[macro_export]
macro_rules! export_wizard {
    ($wizard:ty) => {
        const _: () = {
            struct GerWizardExport;

            impl $crate::__bindings::Guest for GerWizardExport {
                fn describe() -> $crate::__bindings::Description {
                    $crate::__describe::<$wizard>()
                }

                fn expand(
                    args: ::std::vec::Vec<$crate::__bindings::Arg>,
                    state: $crate::__bindings::MachineState,
                ) -> ::std::result::Result<::std::vec::Vec<$crate::__bindings::Statement>, ::std::string::String>
                {
                    $crate::__expand::<$wizard>(args, state)
                }
            }

    $crate::__bindings::export!(GerWizardExport with_types_in $crate::__bindings);
        };
    };
}

#[doc(hidden)]
pub fn __describe<W: Wizard>() -> wit::Description {
    let d = W::describe();
    wit::Description {
        name: d.name,
        summary: d.summary,
        usage: d.usage,
        params: d
            .params
            .into_iter()
            .map(|p| wit::Param { name: p.name, description: p.description, optional: p.optional })
            .collect(),
    }
}

#[doc(hidden)]
pub fn __expand<W: Wizard>(args: Vec<wit::Arg>, state: wit::MachineState) -> Result<Vec<wit::Statement>, String> {
    let description = W::describe();
    let args = Args::new(args.into_iter().map(Arg::from).collect(), &description);
    args.check_count(&description)?;
    let statements = W::expand(&args, &State::from(state))?;
    Ok(statements.into_iter().map(Statement::into_wit).collect())
}
