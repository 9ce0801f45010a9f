//! `run_until`'s fast path must agree with stepping cycle by cycle, on random programs.
mod common;
use common::*;

/// xorshift64*: deterministic, no dependency.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u32 {
        (self.next() % n) as u32
    }
    fn bit(&mut self) -> u32 {
        self.below(2)
    }
}

const BUF: u32 = SRAM_BASE + 0x400;

/// One random register write that the model accepts.
fn random_write(r: &mut Rng, m: &Mcu) -> (u32, u32) {
    let ch = |r: &mut Rng| {
        let mut v = 0;
        for c in 0..2 {
            v |= ccmr::ocm(c).val(r.below(8)) | ccmr::ocpe(c).val(r.bit());
        }
        v
    };
    match r.below(24) {
        0..=2 => {
            let v = cr1::CEN.val(r.below(4).min(1))
                | cr1::URS.val(r.bit())
                | cr1::ARPE.val(r.bit())
                | cr1::OPM.val((r.below(6) == 0) as u32)
                | cr1::UDIS.val((r.below(8) == 0) as u32);
            (TIM1_CR1, v)
        }
        3 => (TIM1_CR2, cr2::MMS.val(r.below(6))),
        4 => (TIM1_DIER, dier::UDE.val(r.bit()) | dier::UIE.val(r.bit())),
        5 => (TIM1_SR, r.next() as u32),
        6 => (TIM1_EGR, egr::UG.mask()),
        7 => (TIM1_CCMR1, ch(r)),
        8 => (TIM1_CCER, (0..2).fold(0, |v, c| v | ccer::cce(c).val(r.below(4).min(1)) | ccer::ccp(c).val(r.bit()))),
        9 => (TIM1_CNT, r.below(64)),
        10 => (TIM1_PSC, r.below(4)),
        11 => (TIM1_ARR, r.below(60)),
        12 => (TIM1_RCR, r.below(4)),
        13 => (TIM1_CCR1, r.below(70)),
        14 => (TIM1_CCR2, r.below(70)),
        15 => (TIM1_BDTR, bdtr::MOE.val(r.below(4).min(1))),
        16 => {
            let (dba, dbl) = if r.bit() == 0 { (off::ARR / 4, r.below(4)) } else { (off::CCR1 / 4, r.below(2)) };
            (TIM1_DCR, dcr::DBA.val(dba) | dcr::DBL.val(dbl))
        }
        17 => (TIM2_CR1, cr1::CEN.val(r.below(4).min(1)) | cr1::ARPE.val(r.bit())),
        18 => (TIM2_SMCR, smcr::SMS.val(if r.bit() == 0 { 0 } else { 7 })),
        19 => [(TIM2_ARR, r.below(40)), (TIM2_PSC, r.below(3)), (TIM2_CNT, r.below(40))][r.below(3) as usize],
        20 => (TIM11_CR1, cr1::CEN.val(r.below(4).min(1)) | cr1::ARPE.val(r.bit())),
        21 => [(TIM11_ARR, r.below(30)), (TIM11_PSC, r.below(4)), (TIM11_EGR, 1)][r.below(3) as usize],
        // Half-word values with a zero upper half, so word transfers stay 16-bit.
        22 => (BUF + 4 * r.below(8), r.below(50)),
        _ => {
            let cr = m.clone().read(DMA2_S5CR);
            (DMA2_S5CR, cr & !dma_cr::EN.mask()) // disable; re-enabled by `reprogram_dma`
        }
    }
}

/// If the stream is idle, clear its flags and start it again with random settings.
fn reprogram_dma(r: &mut Rng, a: &mut Mcu, b: &mut Mcu) {
    if dma_cr::EN.on(a.read(DMA2_S5CR)) || r.below(3) != 0 {
        return;
    }
    let par = if r.bit() == 0 { TIM1_DMAR } else { TIM1_CCR2 };
    let size = if r.bit() == 0 { dma_cr::SIZE_HALF } else { dma_cr::SIZE_WORD };
    let n = 1 + r.below(8);
    let circ = r.bit() == 1;
    for m in [a, b] {
        m.write(DMA2_HIFCR, dma_isr::tcif(5).mask() | dma_isr::htif(5).mask());
        dma5(m, par, BUF, n, size, circ);
    }
}

#[test]
fn run_until_agrees_with_single_steps_on_random_programs() {
    for seed in 1..=std::env::var("FASTPATH_SEEDS").map_or(40u64, |s| s.parse().unwrap()) {
        let mut r = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
        let params = Params {
            dma_latency_cycles: r.below(10),
            tim2_resync_cycles: r.below(6),
            pwm_mode_switch: if r.bit() == 0 { PwmModeSwitch::Reevaluate } else { PwmModeSwitch::OnlyFromFrozen },
            ndtr: if r.bit() == 0 { NdtrReading::AfterTransfer } else { NdtrReading::AtPreload },
            ..Params::default()
        };
        let (mut a, mut b) = (Mcu::new(params), Mcu::new(params));
        for m in [&mut a, &mut b] {
            // DBA at reset is 0 (CR1): point bursts at ARR before any DMA can run.
            m.write(TIM1_DCR, dcr::DBA.val(off::ARR / 4));
        }
        for _ in 0..300 {
            for _ in 0..=r.below(3) {
                let (addr, v) = random_write(&mut r, &a);
                a.write(addr, v);
                b.write(addr, v);
            }
            reprogram_dma(&mut r, &mut a, &mut b);
            let target = a.cycle() + 1 + r.below(400) as u64;
            let before = a.clone();
            a.run_until(target);
            while b.cycle() < target {
                b.step();
            }
            if a != b && std::env::var("FASTPATH_DEBUG").is_ok() {
                debug_divergence(before, target);
            }
            if std::env::var("FASTPATH_STATS").is_ok() && target > 0 && a.cycle() == target && r.below(300) == 0 {
                eprintln!(
                    "seed {seed}: cycle {} edges {} tim2 {} tim11 {} lost {} ndtr {}",
                    a.cycle(),
                    a.edges().len(),
                    a.read(TIM2_CNT),
                    a.tim11_updates(),
                    a.dma_requests_lost(),
                    a.read(DMA2_S5NDTR)
                );
            }
            assert!(
                a == b,
                "seed {seed}: fast path diverged by cycle {target} ({} vs {} edges)",
                a.edges().len(),
                b.edges().len()
            );
        }
    }
}

// A 1 s run at 96 MHz: 100 kHz PWM on PA8 counted by TIM2, a 1 kHz TIM11 tick. The fast
// path has to make this cheap; the counts check it did not skip anything.
#[test]
fn one_second_of_pwm_runs_on_the_fast_path() {
    let mut m = mcu();
    tim2_on(&mut m);
    m.write(TIM1_CR2, cr2::MMS.val(cr2::MMS_OC1REF));
    tim1_ch1(&mut m, 959, 480, ocm::PWM2); // REF low at reset, rises at CNT = 480
    start_tim1(&mut m, 0);
    m.write(TIM11_PSC, 95);
    m.write(TIM11_ARR, 999);
    m.write(TIM11_EGR, egr::UG.mask());
    m.write(TIM11_CR1, cr1::CEN.mask());
    m.run_until(96_000_000);
    assert_eq!(m.read(TIM2_CNT), 100_000);
    assert_eq!(m.edges().len(), 199_999, "100 000 rises, the last fall is after 1 s");
    // UG, then overflows every 96 000 cycles from cycle 96 001 (CNT_EN delay): 999 in 1 s.
    assert_eq!(m.tim11_updates(), 1 + 999);
}

fn tim2_on(m: &mut Mcu) {
    m.write(TIM2_SMCR, smcr::SMS.val(smcr::SMS_EXT_CLOCK_1));
    m.write(TIM2_ARR, u32::MAX);
    m.write(TIM2_CR1, cr1::CEN.mask());
}

/// Print the first cycle where `run_until` and `step` disagree, field by field.
fn debug_divergence(start: Mcu, target: u64) {
    let mut b = start.clone();
    while b.cycle() < target {
        b.step();
        let mut a = start.clone();
        a.run_until(b.cycle());
        if a != b {
            let fa = format!("{a:#?}");
            let fb = format!("{b:#?}");
            let diff: Vec<_> = fa.lines().zip(fb.lines()).filter(|(x, y)| x != y).collect();
            let fs = format!("{start:#?}");
            let st: Vec<_> = fs.lines().filter(|l| !l.trim_start().starts_with(|c: char| c.is_ascii_digit())).collect();
            panic!(
                "diverged at cycle {} (start {}); run_until vs step: {diff:#?}\nstart: {st:#?}",
                b.cycle(),
                start.cycle()
            );
        }
    }
}
