//! The sync core's commands as the image runs them: a hook at the entry of
//! each `COMMANDS` method of its `Controller` writes it to the tape.

use crate::chip::tape::COMMANDS;
use crate::machine::Machine;

/// Hooks the entry of each `COMMANDS` method of the sync core's `Controller`.
pub fn hooks(m: &mut Machine) -> Result<(), String> {
    for (tail, cmd) in COMMANDS {
        let found: Vec<u32> = m
            .image
            .symbols
            .iter()
            // (not the linker's long-branch thunks to it: flash to SRAM)
            .filter(|(n, _)| n.contains("Controller$GT$") && n.contains(tail) && !n.starts_with("__"))
            .map(|(_, &a)| a & !1)
            .collect();
        let [a] = found[..] else {
            return Err(format!("{} functions named like Controller::{}: want one", found.len(), tail));
        };
        let cmd = *cmd;
        m.uc.add_code_hook(a as u64, a as u64, move |uc, _, _| {
            if let Some(t) = uc.get_data_mut().tape.as_mut() {
                t.commands.push((t.ticks.len(), cmd));
            }
        })
        .map_err(|e| format!("unicorn: {e:?}"))?;
    }
    Ok(())
}
