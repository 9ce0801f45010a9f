//! The questions the setup asks a machinist: at a terminal through
//! `dialoguer`, or from a script in tests (`Scripted`).

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

/// A terminal.
pub struct Terminal;

fn cancelled(e: dialoguer::Error) -> CliError {
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
    fn number(&mut self, question: &str, _: Option<u32>, min: u32, max: u32) -> CliResult<u32> {
        let v: u32 = self.next(question)?.parse().map_err(|_| CliError("scripted: not a number".into()))?;
        if (min..=max).contains(&v) {
            Ok(v)
        } else {
            Err(CliError(format!("scripted: {v} outside {min}..={max}")))
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
