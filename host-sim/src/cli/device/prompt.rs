//! The questions the setup asks a machinist: at a terminal through
//! `dialoguer`, or from a script in tests (`Scripted`). A number out of
//! its range is asked again; a refusal of several answers together is
//! asked again through `retry`.

use crate::cli::errors::{CliError, CliResult};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

pub trait Ask {
    /// Says something (the terminal's stderr).
    fn say(&mut self, text: &str);
    /// Waits for Enter after `prompt`.
    fn wait(&mut self, prompt: &str) -> CliResult<()>;
    fn yes(&mut self, question: &str, default: bool) -> CliResult<bool>;
    /// A whole number in `min..=max`.
    fn number(&mut self, question: &str, default: Option<u32>, min: u32, max: u32) -> CliResult<u32>;
    /// One of `choices`; returns its index.
    fn choose(&mut self, question: &str, choices: &[&str]) -> CliResult<usize>;
    /// What a Ctrl-C outside a question ends the command with.
    fn interrupted(&self) -> CliError;
    /// True once a question ended the command (Ctrl-C, or its input
    /// closed): its error is no answer to ask again.
    fn ended(&self) -> bool;
}

/// How often a refused answer is asked again before the setup stops.
pub const TRIES: usize = 3;

/// `question`, asked again after a refusal (said with its reason), at
/// most `TRIES` times. A question that ended the command (Ctrl-C) is no
/// refusal: its error ends the command at once.
pub fn retry<T>(ask: &mut dyn Ask, mut question: impl FnMut(&mut dyn Ask) -> CliResult<T>) -> CliResult<T> {
    let mut last = CliError(String::new());
    for _ in 0..TRIES {
        match question(ask) {
            Ok(v) => return Ok(v),
            Err(e) if ask.ended() => return Err(e),
            Err(e) => {
                ask.say(&format!("refused: {}", e.0));
                last = e;
            }
        }
    }
    Err(CliError(format!("setup: {} ({TRIES} tries): nothing sent", last.0)))
}

/// A terminal, for `command` (named in what a cancel says).
pub struct Terminal {
    command: &'static str,
    /// a read failed: Ctrl-C, or stdin closed or broken
    ended: std::cell::Cell<bool>,
}

/// Ctrl-C was pressed (`Terminal::with_ctrl_c`): the command cleans up on
/// the board (an encoder check stopped) and ends with exit status 130.
static CANCELLED: AtomicBool = AtomicBool::new(false);

/// How long a Ctrl-C leaves the command to end on its own (and stop what
/// it started on the board) before the process ends regardless.
const CANCEL_GRACE: Duration = Duration::from_secs(2);

pub fn cancelled_by_ctrl_c() -> bool {
    CANCELLED.load(Ordering::SeqCst)
}

impl Terminal {
    /// The terminal for `command`'s questions. Ctrl-C interrupts the read
    /// that waits (or the wait the command checks `cancelled_by_ctrl_c`
    /// in), so that the command can stop what it started on the board and
    /// say so once; if it has not ended within CANCEL_GRACE, or at a
    /// second Ctrl-C, the process ends (exit 130) with the cursor shown.
    pub fn with_ctrl_c(command: &'static str) -> Terminal {
        // the handler's own flag: the main thread may have set CANCELLED
        // first, from the interrupted read
        static PRESSED: AtomicBool = AtomicBool::new(false);
        let _ = ctrlc::set_handler(move || {
            show_cursor();
            CANCELLED.store(true, Ordering::SeqCst);
            if !PRESSED.swap(true, Ordering::SeqCst) {
                std::thread::sleep(CANCEL_GRACE);
            }
            eprintln!("error: {command}: cancelled (Ctrl-C): nothing saved");
            std::process::exit(130);
        });
        Terminal { command, ended: std::cell::Cell::new(false) }
    }

    fn cancelled(&self, e: dialoguer::Error) -> CliError {
        show_cursor();
        self.ended.set(true);
        // the read is interrupted by the signal before the handler's
        // thread has set the flag: the same Ctrl-C
        let dialoguer::Error::IO(io) = &e;
        if io.kind() == std::io::ErrorKind::Interrupted {
            CANCELLED.store(true, Ordering::SeqCst);
        }
        match cancelled_by_ctrl_c() {
            true => CliError(format!("{}: cancelled (Ctrl-C): nothing saved", self.command)),
            false => CliError(format!("{}: cancelled ({e}): nothing saved", self.command)),
        }
    }
}

/// dialoguer hides the cursor while a yes/no or a list waits for a key,
/// and leaves it hidden when the wait ends in an error (Ctrl-C is one):
/// shown again (on a terminal only).
fn show_cursor() {
    let _ = dialoguer::console::Term::stderr().show_cursor();
}

impl Ask for Terminal {
    fn say(&mut self, text: &str) {
        eprintln!("{text}");
    }
    fn wait(&mut self, prompt: &str) -> CliResult<()> {
        dialoguer::Input::<String>::new()
            .with_prompt(prompt)
            .allow_empty(true)
            .interact_text()
            .map_err(|e| self.cancelled(e))?;
        Ok(())
    }
    fn yes(&mut self, question: &str, default: bool) -> CliResult<bool> {
        dialoguer::Confirm::new().with_prompt(question).default(default).interact().map_err(|e| self.cancelled(e))
    }
    fn number(&mut self, question: &str, default: Option<u32>, min: u32, max: u32) -> CliResult<u32> {
        // read as text, so that "-5", "1.5" or 20 digits are told the
        // range, not a parser's words
        let mut input = dialoguer::Input::<String>::new().with_prompt(format!("{question} ({min}..={max})"));
        if let Some(d) = default {
            input = input.default(d.to_string());
        }
        let text = input
            .validate_with(move |t: &String| whole_in(t, min, max).map(|_| ()))
            .interact_text()
            .map_err(|e| self.cancelled(e))?;
        whole_in(&text, min, max).map_err(CliError)
    }
    fn interrupted(&self) -> CliError {
        CliError(format!("{}: cancelled (Ctrl-C): nothing saved", self.command))
    }
    fn ended(&self) -> bool {
        self.ended.get() || cancelled_by_ctrl_c()
    }
    fn choose(&mut self, question: &str, choices: &[&str]) -> CliResult<usize> {
        dialoguer::Select::new()
            .with_prompt(question)
            .items(choices)
            .default(0)
            .interact()
            .map_err(|e| self.cancelled(e))
    }
}

/// An answer to a number question: a whole number in `min..=max` (spaces
/// around it taken), else what is wrong with it and the range.
pub fn whole_in(text: &str, min: u32, max: u32) -> Result<u32, String> {
    let t = text.trim();
    match t.parse::<u32>() {
        Ok(v) if (min..=max).contains(&v) => Ok(v),
        Ok(_) => Err(format!("{t} is outside {min}..={max}")),
        // digits too many for a u32 are still a whole number, far outside
        Err(_) if !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit()) => {
            Err(format!("{t} is outside {min}..={max}"))
        }
        Err(_) => Err(format!("'{}' is not a whole number: {min}..={max}", t.escape_debug())),
    }
}

/// Answers given in advance, in order (tests); "^C" is a Ctrl-C at
/// that question.
#[cfg(test)]
pub struct Scripted {
    pub answers: std::collections::VecDeque<String>,
    pub said: Vec<String>,
    ended: bool,
}

#[cfg(test)]
impl Scripted {
    pub fn new(answers: &[&str]) -> Scripted {
        Scripted { answers: answers.iter().map(|s| s.to_string()).collect(), said: vec![], ended: false }
    }
    fn next(&mut self, q: &str) -> CliResult<String> {
        self.said.push(format!("? {q}"));
        match self.answers.pop_front() {
            Some(a) if a == "^C" => {
                self.ended = true;
                Err(self.interrupted())
            }
            Some(a) => Ok(a),
            None => Err(CliError(format!("no answer scripted for '{q}'"))),
        }
    }
}

#[cfg(test)]
impl Ask for Scripted {
    fn say(&mut self, text: &str) {
        self.said.push(text.to_string());
    }
    fn wait(&mut self, prompt: &str) -> CliResult<()> {
        self.next(prompt).map(|_| ())
    }
    fn yes(&mut self, question: &str, _: bool) -> CliResult<bool> {
        Ok(self.next(question)? == "y")
    }
    /// Asks again after an answer out of `min..=max`, as the terminal
    /// does (until the script runs out).
    fn number(&mut self, question: &str, _: Option<u32>, min: u32, max: u32) -> CliResult<u32> {
        loop {
            let a = self.next(question)?;
            match whole_in(&a, min, max) {
                Ok(v) => return Ok(v),
                Err(e) => self.said.push(format!("refused: {e}")),
            }
        }
    }
    fn interrupted(&self) -> CliError {
        CliError("scripted: cancelled (Ctrl-C): nothing saved".into())
    }
    fn ended(&self) -> bool {
        self.ended
    }
    fn choose(&mut self, question: &str, choices: &[&str]) -> CliResult<usize> {
        let a = self.next(question)?;
        choices
            .iter()
            .position(|c| c.starts_with(a.as_str()))
            .ok_or_else(|| CliError(format!("scripted: no choice '{a}'")))
    }
}

#[cfg(test)]
mod tests {
    use super::whole_in;

    #[test]
    fn a_number_answer_is_told_its_range_whatever_was_typed() {
        assert_eq!(whole_in(" 600 ", 1, 250_000), Ok(600));
        assert_eq!(whole_in("0", 1, 250_000), Err("0 is outside 1..=250000".into()));
        assert_eq!(whole_in("99999999999999999999", 1, 20), Err("99999999999999999999 is outside 1..=20".into()));
        for bad in ["-5", "1.5", "", "6OO"] {
            assert_eq!(whole_in(bad, 1, 250_000), Err(format!("'{bad}' is not a whole number: 1..=250000")), "{bad}");
        }
    }
}
