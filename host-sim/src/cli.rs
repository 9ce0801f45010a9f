//! The `polyturn` command line (clap, derive): one module per subcommand,
//! each with its flags, their units, defaults and ranges in `--help`.
//! Errors keep the one-line contract of `errors.rs` and exit status 2.

pub mod cam;
#[cfg(feature = "device")]
pub mod carried;
pub mod compensate;
pub mod console_line;
pub mod cutters;
#[cfg(feature = "device")]
pub mod device;
pub mod errors;
pub mod figures;
#[cfg(feature = "device")]
pub mod flash;
pub mod geometry;
pub mod guided;
pub mod image;
mod limits;
pub mod measure;
#[cfg(test)]
mod names_tests;
pub mod output;
mod ranges;
#[cfg(test)]
mod ranges_tests;
pub mod sequence;
pub mod setup_args;
pub mod setups;
pub mod simulate;
pub mod values;
#[cfg(feature = "device")]
pub mod web;
pub mod x_table;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
pub use errors::{CliError, CliResult, Failed};

pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// Plan, draw and simulate polygon turning with a live rotating cutter.
/// Lengths are in mm, speeds in rpm (lathe) and mm/s (X axis).
#[derive(Parser, Debug)]
#[command(name = "polyturn", version = VERSION, propagate_version = true)]
#[command(disable_help_subcommand = true, arg_required_else_help = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Simulate a hexagon end to end (2:1 x 3 edges at 600 rpm) and draw it
    Demo(simulate::DemoArgs),
    /// What polygon a setup cuts: sides, across flats, flat deviation, corners
    Geometry(geometry::GeometryArgs),
    /// Which setups cut the polygon you want, flattest first
    Setups(setups::SetupsArgs),
    /// Run a setup through the real sync core and a model of the machine
    Simulate(simulate::SimulateArgs),
    /// Talk to the board's console over USB (status, settings, cam upload)
    #[cfg(feature = "device")]
    Device(device::DeviceArgs),
    /// The order in which a single-point tool cuts a sharp polygon's sides
    Sequence(sequence::SequenceArgs),
    /// Plan the X axis that makes the flats straight
    Compensate(compensate::CompensateArgs),
    /// Smooth single-point tool paths for a sharp polygon, and the cam table
    Cam(cam::CamArgs),
    /// Write firmware to the board over USB through its ROM bootloader (BOOT0), no probe
    #[cfg(feature = "device")]
    Flash(flash::FlashArgs),
    /// The page: plan, preview, simulate, and the board over WebSerial and WebUSB, served on localhost
    #[cfg(feature = "device")]
    Web(web::WebArgs),
    /// Make the release .bin and .hex from the firmware ELF
    Image(image::ImageArgs),
    /// Print a shell completion script (e.g. `polyturn completions bash > /etc/bash_completion.d/polyturn`)
    Completions {
        /// The shell: bash, zsh, fish, elvish or powershell
        shell: clap_complete::Shell,
    },
}

/// Runs one command line (without the program name); Ok(text) to print,
/// or Err for exit status 2.
pub fn dispatch(argv: &[String]) -> CliResult<String> {
    dispatch_reported(argv).map_err(|f| f.error)
}

/// `dispatch`, keeping the report of a command that failed after making
/// it (`Failed`): what the `polyturn` binary prints.
pub fn dispatch_reported(argv: &[String]) -> Result<String, Failed> {
    let parsed = command()
        .try_get_matches_from(std::iter::once("polyturn".to_string()).chain(argv.iter().cloned()))
        .and_then(|m| Cli::from_arg_matches(&m));
    let cli = match errors::adapt(parsed)? {
        errors::Parsed::Run(cli) => cli,
        errors::Parsed::Print(text) => return Ok(text),
    };
    Ok(match cli.command {
        Command::Simulate(a) => return simulate::run_cli(a),
        Command::Demo(a) => simulate::demo(a),
        Command::Geometry(a) => geometry::run(a),
        Command::Setups(a) => setups::run(a),
        #[cfg(feature = "device")]
        Command::Device(a) => device::run(a),
        Command::Sequence(a) => sequence::run(a),
        Command::Compensate(a) => compensate::run(a),
        Command::Cam(a) => cam::run(a),
        #[cfg(feature = "device")]
        Command::Flash(a) => flash::run(a),
        #[cfg(feature = "device")]
        Command::Web(a) => web::run(a),
        Command::Image(a) => image::run(a),
        Command::Completions { shell } => Ok(completions(shell)),
    }?)
}

/// The command line, with negative numbers taken as values at every depth
/// (so that `--ratio -2` is refused as a ratio, naming --ratio, not as a
/// flag), and so is any value given to an option (`--rpm -inf`, which is
/// no negative number to clap, is refused by `--rpm`'s own range); each
/// flag's help says the range its parser refuses by (`ranges.rs`).
pub fn command() -> clap::Command {
    ranges::in_help(hyphen_values(Cli::command()))
}

fn hyphen_values(c: clap::Command) -> clap::Command {
    c.allow_negative_numbers(true)
        .mut_args(|a| {
            let option = a.get_long().is_some() && a.get_action().takes_values();
            if option {
                a.allow_hyphen_values(true)
            } else {
                a
            }
        })
        .mut_subcommands(hyphen_values)
}

fn completions(shell: clap_complete::Shell) -> String {
    let mut out = Vec::new();
    clap_complete::generate(shell, &mut command(), "polyturn", &mut out);
    String::from_utf8_lossy(&out).trim_end().to_string()
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_command_line_definition_is_consistent() {
        super::command().debug_assert();
    }

    /// Every option of every command, as (the command's path, `--long`).
    fn options(c: &clap::Command, path: &[String], out: &mut Vec<(Vec<String>, String)>) {
        for a in c.get_arguments().filter(|a| a.get_action().takes_values()) {
            if let Some(long) = a.get_long() {
                out.push((path.to_vec(), format!("--{long}")));
            }
        }
        for s in c.get_subcommands() {
            options(s, &[path, &[s.get_name().to_string()]].concat(), out);
        }
    }

    #[test]
    fn a_non_finite_or_negative_value_is_taken_as_the_options_value_at_every_depth() {
        let mut all = Vec::new();
        options(&super::command(), &[], &mut all);
        assert!(all.len() > 60, "the walk found the options ({})", all.len());
        assert!(all.iter().any(|(p, o)| p == &["device", "selftest"] && o == "--rpm"), "nested commands too");
        for (path, option) in &all {
            for value in ["-inf", "-nan", "-1", "-0"] {
                let argv: Vec<String> = path.iter().cloned().chain([option.clone(), value.into()]).collect();
                let said = match super::command().try_get_matches_from(std::iter::once("polyturn".into()).chain(argv)) {
                    Ok(_) => continue,
                    Err(e) => e.to_string(),
                };
                assert!(
                    !said.contains("unexpected argument") && !said.contains("a value is required"),
                    "{path:?} {option} {value}: {said}"
                );
            }
        }
    }
}
