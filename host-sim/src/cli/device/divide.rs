//! `polyturn device divide N`: the board divides a turn into N (`divide
//! N`: the cutter stays off) and streams its status (`watch`); each line's
//! readout is shown, in large digits on a terminal, until Ctrl-C, which
//! ends the watch and the dividing on the board (`divide stop`).

use super::session::{ok_or_device_error, Session};
use crate::cli::errors::{escaped, CliResult};
use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::sync::atomic::AtomicBool;

/// How the readout is shown: large digits redrawn in place (a terminal),
/// or a line of text for each status line (a pipe, a file).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Look {
    Big,
    Plain,
}

/// The readout of a status line (`console/divide.rs`'s fields).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Readout {
    pub divisions: String,
    pub division: String,
    pub division_deg: String,
    pub to_deg: String,
    pub to_counts: String,
    pub within: bool,
    pub angle_deg: String,
    pub from_index: bool,
    /// a latched fault, by name
    pub fault: Option<String>,
}

impl Readout {
    /// The readout in a status line or in `divide`'s reply; None without
    /// one (the board is not dividing).
    pub fn parse(line: &str) -> Option<Readout> {
        let f: BTreeMap<&str, &str> = line.split_whitespace().filter_map(|w| w.split_once('=')).collect();
        let get = |k: &str| f.get(k).map(|v| v.to_string());
        Some(Readout {
            divisions: get("divide")?,
            division: get("division")?,
            division_deg: get("division_deg")?,
            to_deg: get("to_deg")?,
            to_counts: get("to_counts")?,
            within: f.get("within") == Some(&"yes"),
            angle_deg: get("angle_deg")?,
            from_index: f.get("angle_from") == Some(&"index"),
            fault: get("fault").filter(|f| f != "none"),
        })
    }

    /// `+0.2` for `0.2`: the way to turn, always signed (0 unsigned).
    fn signed(v: &str) -> String {
        match v.starts_with('-') || v.trim_matches(['0', '.']).is_empty() {
            true => v.to_string(),
            false => format!("+{v}"),
        }
    }

    fn origin(&self) -> &'static str {
        match self.from_index {
            true => "from the index",
            false => "from where the board started: no index seen yet, turn past it to fix the origin",
        }
    }

    fn verdict(&self) -> &'static str {
        if self.within {
            "WITHIN ±1 count"
        } else {
            "not there"
        }
    }

    /// One line of text.
    pub fn plain(&self) -> String {
        let fault = self.fault.as_ref().map(|f| format!(" | FAULT {f}")).unwrap_or_default();
        format!(
            "division {} of {} ({}°): turn {}° ({} counts): {} | spindle {}° {}{fault}",
            self.division,
            self.divisions,
            self.division_deg,
            Readout::signed(&self.to_deg),
            Readout::signed(&self.to_counts),
            self.verdict(),
            self.angle_deg,
            self.origin(),
        )
    }

    /// The lines of the large readout: the division, the way to it in
    /// large digits (green within the tolerance), the counts and the
    /// spindle's angle.
    pub fn big(&self) -> Vec<String> {
        let (on, off) = if self.within { ("\x1b[1;32m", "\x1b[0m") } else { ("\x1b[1m", "\x1b[0m") };
        let mut lines = vec![format!("DIVISION {} OF {}  at {}°", self.division, self.divisions, self.division_deg)];
        lines
            .extend(large(&format!("{}°", Readout::signed(&self.to_deg))).into_iter().map(|l| format!("{on}{l}{off}")));
        lines.push(format!("{on}{} counts to turn   {}{off}", Readout::signed(&self.to_counts), self.verdict()));
        lines.push(format!("spindle {}° {}", self.angle_deg, self.origin()));
        if let Some(f) = &self.fault {
            lines.push(format!("FAULT {f}: the readout may be off, see status"));
        }
        lines
    }
}

/// Each character's 5 rows, 3 cells wide (`#` is ink).
fn glyph(c: char) -> [&'static str; 5] {
    match c {
        '0' => ["###", "# #", "# #", "# #", "###"],
        '1' => [" ##", "  #", "  #", "  #", "  #"],
        '2' => ["###", "  #", "###", "#  ", "###"],
        '3' => ["###", "  #", "###", "  #", "###"],
        '4' => ["# #", "# #", "###", "  #", "  #"],
        '5' => ["###", "#  ", "###", "  #", "###"],
        '6' => ["###", "#  ", "###", "# #", "###"],
        '7' => ["###", "  #", "  #", "  #", "  #"],
        '8' => ["###", "# #", "###", "# #", "###"],
        '9' => ["###", "# #", "###", "  #", "###"],
        '-' => ["   ", "   ", "###", "   ", "   "],
        '+' => ["   ", " # ", "###", " # ", "   "],
        '.' => ["   ", "   ", "   ", "   ", " # "],
        '°' => ["###", "# #", "###", "   ", "   "],
        _ => ["   "; 5],
    }
}

/// `text` in large digits: 5 rows, each cell two block characters wide.
pub fn large(text: &str) -> Vec<String> {
    (0..5)
        .map(|row| {
            let cells: Vec<String> =
                text.chars().map(|c| glyph(c)[row].replace('#', "██").replace(' ', "  ")).collect();
            cells.join("  ").trim_end().to_string()
        })
        .collect()
}

/// What a status line shows: the readout's frame (redrawn over the last
/// on a terminal), or the line itself when it has none.
struct Screen {
    look: Look,
    /// lines the last frame took (a terminal)
    drawn: usize,
}

impl Screen {
    fn show(&mut self, line: &str) -> String {
        let Some(r) = Readout::parse(line) else { return escaped(line) };
        match self.look {
            Look::Plain => r.plain(),
            Look::Big => {
                let lines = r.big();
                // up over the last frame, each line cleared before it is drawn
                let up = if self.drawn > 0 { format!("\x1b[{}A", self.drawn) } else { String::new() };
                self.drawn = lines.len();
                let body: Vec<String> = lines.iter().map(|l| format!("\x1b[2K{l}")).collect();
                format!("{up}{}", body.join("\n"))
            }
        }
    }
}

/// Sends `line` (`divide N`), then shows the readout until `stop` (Ctrl-C)
/// or the reader goes away; ends the watch and the dividing on the board.
pub fn divide<P: Read + Write>(
    s: &mut Session<P>,
    line: &str,
    out: &mut impl Write,
    stop: &AtomicBool,
    look: Look,
) -> CliResult<String> {
    ok_or_device_error(s.ask(line)?)?;
    let mut screen = Screen { look, drawn: 0 };
    super::stream(s, out, stop, |l| screen.show(l))?;
    ok_or_device_error(s.ask("divide stop")?)
}
