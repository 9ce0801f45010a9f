//! The `polyturn` command line: one module per subcommand.

pub mod args;
pub mod cam;
pub mod compensate;
pub mod device;
pub mod geometry;
pub mod sequence;
pub mod setups;
pub mod simulate;

use args::CliError;

pub const VERSION: &str = env!("CARGO_PKG_VERSION");

pub fn help() -> String {
    format!(
        "polyturn {VERSION}: plan, draw and simulate polygon turning with a live rotating cutter\n\n\
         usage:\n  polyturn demo                 simulate a hexagon end to end, write hexagon.svg\n  \
         {}\n  {}\n  {}\n  {}\n  {}\n  {}\n  {}\n  \
         polyturn --help | --version\n\n\
         Lengths are in mm. `polyturn <command> --help` shows a command's flags.",
        geometry::USAGE,
        setups::USAGE,
        simulate::USAGE,
        device::USAGE,
        sequence::USAGE,
        compensate::USAGE,
        cam::USAGE
    )
}

/// Runs one command line; Ok(text) to print, or Err for exit status 2.
pub fn dispatch(argv: &[String]) -> Result<String, CliError> {
    let (cmd, rest) = match argv.split_first() {
        Some((c, r)) => (c.as_str(), r),
        None => return Ok(help()),
    };
    if rest.iter().any(|a| a == "--help" || a == "-h") {
        return Ok(usage_of(cmd).unwrap_or_else(help));
    }
    match cmd {
        "--help" | "-h" | "help" => Ok(help()),
        "--version" | "-V" => Ok(format!("polyturn {VERSION}")),
        "geometry" => geometry::run(rest),
        "simulate" => simulate::run_cli(rest),
        "setups" => setups::run(rest),
        "device" => device::run(rest),
        "sequence" => sequence::run(rest),
        "compensate" => compensate::run(rest),
        "cam" => cam::run(rest),
        "demo" => simulate::demo(rest),
        other => Err(CliError(format!("unknown command '{other}' (try polyturn --help)"))),
    }
}

fn usage_of(cmd: &str) -> Option<String> {
    let u = match cmd {
        "geometry" => geometry::USAGE,
        "simulate" => simulate::USAGE,
        "setups" => setups::USAGE,
        "device" => device::USAGE,
        "sequence" => sequence::USAGE,
        "compensate" => compensate::USAGE,
        "cam" => cam::USAGE,
        "demo" => "polyturn demo [--svg FILE] [--json]",
        _ => return None,
    };
    Some(format!("usage: {u}"))
}
