//! The timers' internal trigger connections: which ITRx input of a slave timer carries
//! which master's TRGO. RM0383 §13.4.3 gives them in the table "TIMx internal trigger
//! connection" under TIMx_SMCR.TS; the rows are those of the same timers' table in
//! RM0090 (its Table 98: TIM2 ← TIM1, TIM8, TIM3, TIM4; TIM3 ← TIM1, TIM2, TIM5, TIM4;
//! TIM4 ← TIM1, TIM2, TIM3, TIM8; TIM5 ← TIM2, TIM3, TIM4, TIM8), less TIM8, which the
//! STM32F411 does not have (RM0383 §2.3 Table 1): those entries, and TIM2's ITR1
//! (remapped by TIM2_OR, §13.4.19), are left empty. The board uses TIM1 → TIM2 (ITR0,
//! the step count) and TIM3 → TIM5 (ITR1, the lathe's edge times).

use super::GpTimer;

/// (slave, [its ITR0, ITR1, ITR2, ITR3 masters]); "" where nothing is modelled.
pub const ITR: [(&str, [&str; 4]); 4] = [
    ("TIM2", ["TIM1", "", "TIM3", "TIM4"]),
    ("TIM3", ["TIM1", "TIM2", "TIM5", "TIM4"]),
    ("TIM4", ["TIM1", "TIM2", "TIM3", ""]),
    ("TIM5", ["TIM2", "TIM3", "TIM4", ""]),
];

/// The ITRx of `slave` that carries `master`'s TRGO, if any.
pub fn itr(slave: &str, master: &str) -> Option<u32> {
    let (_, row) = ITR.iter().find(|r| r.0 == slave)?;
    row.iter().position(|&m| !m.is_empty() && m == master).map(|i| i as u32)
}

/// `master`'s TRGO pulses since the last call, delivered to each of `slaves` (name,
/// timer) whose ITR table row names `master`; returns how many. The pulses reach
/// the slaves at the time the models stand at (their resynchronisation is not
/// modelled).
pub fn route(master_name: &str, master: &mut GpTimer, slaves: &mut [(&str, &mut GpTimer)]) -> u32 {
    let pulses = master.take_trgo();
    for (name, slave) in slaves.iter_mut() {
        let Some(n) = itr(name, master_name) else { continue };
        for _ in 0..pulses {
            slave.trigger(n);
        }
    }
    pulses
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::addr::off::{CCER, CCMR1, CCMR2, CCR1, CR1, CR2, SMCR};
    use crate::bits::{ccer, ccmr, ccmr_in, cr2, smcr};

    #[test]
    fn tim5s_itr1_is_tim3s_trgo_and_tim2s_itr0_tim1s() {
        assert_eq!(itr("TIM5", "TIM3"), Some(1));
        assert_eq!(itr("TIM2", "TIM1"), Some(0), "the step count's link (tim2.rs)");
        assert_eq!(itr("TIM4", "TIM3"), Some(2));
        assert_eq!(itr("TIM5", "TIM8"), None, "no TIM8 on the F411");
        assert_eq!(itr("TIM3", "TIM3"), None);
    }

    /// TIM3 capturing on A's rise with MMS = 011, TIM5 capturing on TRC from ITR1:
    /// CCR3 takes TIM5's count at the edge; TIM4 (ITR2 from TIM3, no TRC channel)
    /// is untouched.
    #[test]
    fn a_capture_on_tim3_latches_tim5s_count_through_itr1() {
        let mut tim3 = GpTimer::new(16, 4);
        tim3.write(SMCR, smcr::SMS.val(smcr::SMS_ENCODER_3), u32::MAX);
        tim3.write(CCMR1, ccmr::ccs(0).val(ccmr_in::CCS_TI), u32::MAX);
        tim3.write(CCER, ccer::cce(0).mask(), u32::MAX);
        tim3.write(CR2, cr2::MMS.val(cr2::MMS_COMPARE_PULSE), u32::MAX);
        tim3.write(CR1, 1, u32::MAX);
        let mut tim5 = GpTimer::new(32, 4);
        tim5.write(SMCR, smcr::TS.val(smcr::TS_ITR1), u32::MAX);
        tim5.write(CCMR2, ccmr::ccs(0).val(ccmr_in::CCS_TRC), u32::MAX);
        tim5.write(CCER, ccer::cce(2).mask(), u32::MAX);
        tim5.write(CR1, 1, u32::MAX);
        let mut tim4 = GpTimer::new(16, 4);
        tim5.advance(777, 1, 1);
        tim3.inputs([true, false, false]);
        route("TIM3", &mut tim3, &mut [("TIM4", &mut tim4), ("TIM5", &mut tim5)]);
        assert_eq!(tim5.read(CCR1 + 8), 777);
        assert_eq!(tim4.read(crate::addr::off::SR), 0);
        route("TIM3", &mut tim3, &mut [("TIM5", &mut tim5)]);
        tim5.advance(900, 1, 1);
        route("TIM3", &mut tim3, &mut [("TIM5", &mut tim5)]);
        assert_eq!(tim5.read(CCR1 + 8), 777, "each pulse is delivered once");
    }
}
