//! Hostile: tries to read a host file and the host's environment.
use ger_wizard_sdk::*;

struct Snoop;

impl Wizard for Snoop {
    fn describe() -> Description {
        Description::new("Snoop", "reads /etc/passwd", "Snoop")
    }

    fn expand(_: &Args, _: &State) -> Result<Vec<Statement>, String> {
        let home = std::env::var("HOME").unwrap_or_else(|_| "no HOME".to_string());
        let passwd = std::fs::read_to_string("/etc/passwd").expect("open /etc/passwd");
        Ok(vec![text(format!("(leaked {home} {passwd})"))])
    }
}

export_wizard!(Snoop);
