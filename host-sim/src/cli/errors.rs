//! The CLI's error contract: one line, `error: --FLAG what is allowed
//! (got 'value')`, exit status 2. clap's own errors are adapted to it, and
//! every value echoed back is escaped so that no input can add a line.

mod missing;

use clap::error::{ContextKind, ContextValue, ErrorKind};

/// A refused command line: one line, naming the flag where there is one.
#[derive(Debug, Clone, PartialEq)]
pub struct CliError(pub String);

impl CliError {
    pub fn flag(flag: &str, msg: impl std::fmt::Display) -> CliError {
        CliError(format!("--{flag} {msg}"))
    }
}

pub type CliResult<T> = Result<T, CliError>;

/// A command that failed, with the report it made first where it ran to
/// the end (a simulation whose controller latched a fault): the report
/// still goes to stdout, so that a script reading `--json` gets it whole,
/// and the one-line error to stderr with exit status 2.
#[derive(Debug, Clone, PartialEq)]
pub struct Failed {
    pub report: Option<String>,
    pub error: CliError,
}

impl From<CliError> for Failed {
    fn from(error: CliError) -> Failed {
        Failed { report: None, error }
    }
}

/// What clap's verdict on a command line becomes.
pub enum Parsed<T> {
    Run(T),
    /// `--help`, `--version`: text for stdout, exit 0.
    Print(String),
}

/// Turns clap's result into ours.
pub fn adapt<T>(r: Result<T, clap::Error>) -> CliResult<Parsed<T>> {
    let e = match r {
        Ok(v) => return Ok(Parsed::Run(v)),
        Err(e) => e,
    };
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            Ok(Parsed::Print(e.render().to_string().trim_end().to_string()))
        }
        _ => Err(CliError(one_line(&e))),
    }
}

fn one_line(e: &clap::Error) -> String {
    let arg = flag_of(e);
    let got = || text(e, ContextKind::InvalidValue).map(|v| format!(" (got '{}')", escaped(&v))).unwrap_or_default();
    match e.kind() {
        ErrorKind::ValueValidation => {
            let why = std::error::Error::source(e).map(|s| s.to_string()).unwrap_or_else(|| "is not valid".into());
            format!("{} {}{}", arg, escaped(&why), got())
        }
        ErrorKind::InvalidValue if text(e, ContextKind::InvalidValue).as_deref() == Some("") => {
            format!("{arg} needs a value")
        }
        ErrorKind::InvalidValue => {
            let valid = strings(e, ContextKind::ValidValue).join(", ");
            format!("{arg} must be one of {valid}{}", got())
        }
        ErrorKind::ArgumentConflict if strings(e, ContextKind::PriorArg).iter().any(|p| name(p) == arg) => {
            format!("{arg} is given twice (give it once)")
        }
        ErrorKind::ArgumentConflict => {
            let prior = strings(e, ContextKind::PriorArg).iter().map(|p| name(p)).collect::<Vec<_>>().join(", ");
            format!("{arg} cannot be given with {prior}: give one of them")
        }
        ErrorKind::MissingRequiredArgument => missing::sentence(e),
        ErrorKind::UnknownArgument if arg.starts_with("--") && arg.contains('=') => {
            format!("{} takes no value (got '{}')", name(&arg), escaped(&arg))
        }
        ErrorKind::UnknownArgument if arg.starts_with('-') => {
            format!("{} is not a flag of this command (see --help)", escaped(&arg))
        }
        ErrorKind::UnknownArgument => format!("unexpected argument '{}' (see --help)", escaped(&arg)),
        ErrorKind::TooManyValues | ErrorKind::NoEquals => {
            format!("{} takes no value{}", name(&arg), got())
        }
        ErrorKind::InvalidSubcommand => {
            format!(
                "unknown command '{}' (see polyturn --help)",
                escaped(&text(e, ContextKind::InvalidSubcommand).unwrap_or_default())
            )
        }
        _ => {
            // anything else: clap's first line, without its prefix
            let r = e.render().to_string();
            escaped(r.lines().next().unwrap_or("").trim_start_matches("error: "))
        }
    }
}

/// `--depth <MM>` → `--depth`; a positional `<FILE>` or `[NAME]` → `FILE`, `NAME`.
fn name(arg: &str) -> String {
    arg.split([' ', '=']).next().unwrap_or(arg).trim_start_matches(['<', '[']).trim_end_matches(['>', ']']).to_string()
}

fn flag_of(e: &clap::Error) -> String {
    match e.get(ContextKind::InvalidArg) {
        Some(ContextValue::String(s)) if e.kind() == ErrorKind::UnknownArgument => s.clone(),
        Some(ContextValue::String(s)) => name(s),
        Some(ContextValue::Strings(v)) => v.first().map(|s| name(s)).unwrap_or_default(),
        _ => String::new(),
    }
}

fn text(e: &clap::Error, k: ContextKind) -> Option<String> {
    match e.get(k) {
        Some(ContextValue::String(s)) => Some(s.clone()),
        _ => None,
    }
}

fn strings(e: &clap::Error, k: ContextKind) -> Vec<String> {
    match e.get(k) {
        Some(ContextValue::Strings(v)) => v.clone(),
        Some(ContextValue::String(s)) => vec![s.clone()],
        _ => vec![],
    }
}

/// Control characters (a newline, an escape) shown as escapes, so an echoed
/// value can neither add a line nor move the terminal's cursor.
pub fn escaped(s: &str) -> String {
    s.chars().flat_map(|c| if c.is_control() { c.escape_default().collect::<Vec<_>>() } else { vec![c] }).collect()
}
