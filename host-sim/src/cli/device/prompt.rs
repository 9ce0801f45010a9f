//! The questions the setup asks a machinist: at a terminal through
//! `dialoguer`, or from a script in tests (`Scripted`). A number out of
//! its range is asked again; a refusal of several answers together is
//! asked again through `retry`.

use crate::cli::errors::{CliError, CliResult};

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
}

/// How often a refused answer is asked again before the setup stops.
pub const TRIES: usize = 3;

/// `question`, asked again after a refusal (said with its reason), at
/// most `TRIES` times.
pub fn retry<T>(ask: &mut dyn Ask, mut question: impl FnMut(&mut dyn Ask) -> CliResult<T>) -> CliResult<T> {
    let mut last = CliError(String::new());
    for _ in 0..TRIES {
        match question(ask) {
            Ok(v) => return Ok(v),
            Err(e) => {
                ask.say(&format!("refused: {}", e.0));
                last = e;
            }
        }
    }
    Err(CliError(format!("setup: {} ({TRIES} tries): nothing sent", last.0)))
}

/// A terminal.
pub struct Terminal;

impl Terminal {
    /// The terminal for the setup's questions: Ctrl-C between two reads of
    /// a key (a signal, not a key) gives the cursor back before it ends
    /// the setup, as a Ctrl-C read as a key does (`cancelled`).
    pub fn with_ctrl_c() -> Terminal {
        let _ = ctrlc::set_handler(|| {
            show_cursor();
            eprintln!("error: setup: cancelled (Ctrl-C): nothing saved");
            std::process::exit(130);
        });
        Terminal
    }
}

/// dialoguer hides the cursor while a yes/no or a list waits for a key,
/// and leaves it hidden when the wait ends in an error (Ctrl-C is one):
/// shown again (on a terminal only).
fn show_cursor() {
    let _ = dialoguer::console::Term::stderr().show_cursor();
}

fn cancelled(e: dialoguer::Error) -> CliError {
    show_cursor();
    CliError(format!("setup: cancelled ({e}): nothing saved"))
}

impl Ask for Terminal {
    fn say(&mut self, text: &str) {
        eprintln!("{text}");
    }
    fn wait(&mut self, prompt: &str) -> CliResult<()> {
        dialoguer::Input::<String>::new().with_prompt(prompt).allow_empty(true).interact_text().map_err(cancelled)?;
        Ok(())
    }
    fn yes(&mut self, question: &str, default: bool) -> CliResult<bool> {
        dialoguer::Confirm::new().with_prompt(question).default(default).interact().map_err(cancelled)
    }
    fn number(&mut self, question: &str, default: Option<u32>, min: u32, max: u32) -> CliResult<u32> {
        let mut input = dialoguer::Input::<u32>::new().with_prompt(format!("{question} ({min}..={max})"));
        if let Some(d) = default {
            input = input.default(d);
        }
        input
            .validate_with(move |v: &u32| if (min..=max).contains(v) { Ok(()) } else { Err(format!("{min}..={max}")) })
            .interact_text()
            .map_err(cancelled)
    }
    fn choose(&mut self, question: &str, choices: &[&str]) -> CliResult<usize> {
        dialoguer::Select::new().with_prompt(question).items(choices).default(0).interact().map_err(cancelled)
    }
}

/// Answers given in advance, in order (tests).
#[cfg(test)]
pub struct Scripted {
    pub answers: std::collections::VecDeque<String>,
    pub said: Vec<String>,
}

#[cfg(test)]
impl Scripted {
    pub fn new(answers: &[&str]) -> Scripted {
        Scripted { answers: answers.iter().map(|s| s.to_string()).collect(), said: vec![] }
    }
    fn next(&mut self, q: &str) -> CliResult<String> {
        self.said.push(format!("? {q}"));
        self.answers.pop_front().ok_or_else(|| CliError(format!("no answer scripted for '{q}'")))
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
            match a.parse::<u32>() {
                Ok(v) if (min..=max).contains(&v) => return Ok(v),
                _ => self.said.push(format!("refused: {a}: {min}..={max}")),
            }
        }
    }
    fn choose(&mut self, question: &str, choices: &[&str]) -> CliResult<usize> {
        let a = self.next(question)?;
        choices
            .iter()
            .position(|c| c.starts_with(a.as_str()))
            .ok_or_else(|| CliError(format!("scripted: no choice '{a}'")))
    }
}
