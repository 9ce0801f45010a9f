//! The time-base unit every timer here shares: counter, prescaler, auto-reload.
//! RM0383 §12.3.1 (TIM1), §13.3.1 (TIM2..5), §14.3.1 (TIM9..11) describe the same
//! unit; RM0090 §17.3.1/§18.3.1 and RM0401 §14.3.1 have the same text.

/// What one CK_PSC pulse did to the counter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Tick {
    /// The prescaler counted, or the counter is blocked (ARR = 0): CNT unchanged.
    Idle,
    /// CNT went up by one (or rolled from its maximum to 0 while above ARR).
    Count,
    /// CNT was equal to the ARR shadow and restarted from 0: counter overflow (§12.3.2).
    Overflow,
}

/// Counter, prescaler and auto-reload with their preload/shadow pairs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct TimeBase {
    /// CR1.CEN as software (or OPM) left it.
    pub cen: bool,
    /// CNT_EN: "the actual counter enable signal CNT_EN is set 1 clock cycle after CEN"
    /// (§12.3.1 / §13.3.1 / §14.3.1, "Time-base unit").
    cnt_en: bool,
    pub udis: bool,
    pub urs: bool,
    pub opm: bool,
    pub arpe: bool,
    pub cnt: u32,
    /// TIMx_PSC as written; "the new prescaler ratio is taken into account at the next
    /// update event" (§12.3.1 "Prescaler description").
    pub psc: u32,
    psc_active: u32,
    psc_cnt: u32,
    /// TIMx_ARR as written (the preload register).
    pub arr: u32,
    /// The ARR shadow register the counter compares with.
    pub arr_active: u32,
    /// Largest CNT value: 0xFFFF for 16-bit counters, 0xFFFF_FFFF for TIM2 (§13.1).
    max: u32,
    pub uif: bool,
}

impl TimeBase {
    /// CR1's time-base bits from a written value: CEN, UDIS, URS, OPM, ARPE
    /// (§12.4.1, §13.4.1, §14.5.1; OPM is reserved, so 0, on TIM10/11).
    pub fn write_cr1(&mut self, v: u32) {
        use crate::bits::cr1;
        self.cen = cr1::CEN.on(v);
        self.udis = cr1::UDIS.on(v);
        self.urs = cr1::URS.on(v);
        self.opm = cr1::OPM.on(v);
        self.set_arpe(cr1::ARPE.on(v));
    }

    /// Those bits as CR1 reads them back.
    pub fn cr1(&self) -> u32 {
        use crate::bits::cr1;
        cr1::CEN.val(self.cen as u32)
            | cr1::UDIS.val(self.udis as u32)
            | cr1::URS.val(self.urs as u32)
            | cr1::OPM.val(self.opm as u32)
            | cr1::ARPE.val(self.arpe as u32)
    }

    /// Reset state: every register 0 (ARR reset value is 0 on these parts, see the
    /// TIMx_ARR descriptions §12.4.12, §13.4.12, §14.5.9).
    pub fn new(max: u32) -> TimeBase {
        TimeBase {
            cen: false,
            cnt_en: false,
            udis: false,
            urs: false,
            opm: false,
            arpe: false,
            cnt: 0,
            psc: 0,
            psc_active: 0,
            psc_cnt: 0,
            arr: 0,
            arr_active: 0,
            max,
            uif: false,
        }
    }

    /// One CK_INT edge of the enable path. Returns CNT_EN for this cycle and latches
    /// CEN into CNT_EN for the next one (1-cycle delay, §12.3.1).
    pub fn latch_enable(&mut self) -> bool {
        let run = self.cnt_en;
        self.cnt_en = self.cen;
        run
    }

    /// CNT_EN as it stands (what the next cycle will count with).
    pub fn counting(&self) -> bool {
        self.cnt_en
    }

    /// Whether CNT_EN already equals CEN (no enable change in flight).
    pub fn enable_settled(&self) -> bool {
        self.cnt_en == self.cen
    }

    /// Stop at once: OPM at an update event clears CEN (§12.4.1 OPM/CEN bits).
    pub fn stop(&mut self) {
        self.cen = false;
        self.cnt_en = false;
    }

    /// One CK_PSC pulse: the prescaler counts 0..=PSC and the counter advances when it
    /// wraps (§12.3.1, Figures "Counter timing diagram with prescaler division change").
    pub fn clock(&mut self) -> Tick {
        if self.psc_cnt < self.psc_active {
            self.psc_cnt += 1;
            return Tick::Idle;
        }
        self.psc_cnt = 0;
        // "The counter is blocked while the auto-reload value is null" (§13.4.12 ARR).
        if self.arr_active == 0 {
            return Tick::Idle;
        }
        // Upcounting: "the counter counts from 0 to the auto-reload value, then restarts
        // from 0 and generates a counter overflow event" (§12.3.2 "Upcounting mode").
        if self.cnt == self.arr_active {
            self.cnt = 0;
            Tick::Overflow
        } else {
            // Above ARR (ARR lowered without preload): the manual says nothing; the
            // counter runs to its maximum and rolls over to 0 without an overflow event.
            self.cnt = self.cnt.wrapping_add(1) & self.max;
            Tick::Count
        }
    }

    /// Shadow transfer at an update event: prescaler buffer and ARR shadow take their
    /// preload values (§12.3.1, §12.3.2 "When an update event occurs...").
    pub fn load_shadows(&mut self) {
        self.psc_active = self.psc;
        self.arr_active = self.arr;
    }

    /// UG: "Re-initialize the counter and generates an update of the registers. Note that
    /// the prescaler counter is cleared too (anyway the prescaler ratio is not affected)"
    /// (§12.4.6 EGR.UG). Returns nothing: the caller decides about the update event,
    /// which UDIS may forbid while the re-initialisation still happens (§12.4.1 UDIS).
    /// UG (§12.4.6, §13.4.6, §14.5.4): counter and prescaler counter
    /// re-initialised even when UDIS = 1; true when the update event follows
    /// (UDIS = 0, §12.4.1).
    pub fn ug(&mut self) -> bool {
        self.cnt = 0;
        self.psc_cnt = 0;
        !self.udis
    }

    /// A write to SR: UIF is rc_w0 (§12.4.5, §13.4.5, §14.5.3).
    pub fn write_uif(&mut self, v: u32) {
        if !crate::bits::sr::UIF.on(v) {
            self.uif = false;
        }
    }

    /// TIMx_ARR write: with ARPE = 0 the shadow follows at once (§12.3.1: "transferred in
    /// the shadow register permanently or at each update event, depending on ARPE").
    pub fn write_arr(&mut self, value: u32) {
        self.arr = value;
        if !self.arpe {
            self.arr_active = value;
        }
    }

    /// CR1.ARPE changed: with ARPE = 0 the transfer is permanent, so the shadow follows.
    pub fn set_arpe(&mut self, arpe: bool) {
        self.arpe = arpe;
        if !arpe {
            self.arr_active = self.arr;
        }
    }

    /// How many counter ticks (1-based) until the next one that wraps CNT to 0
    /// (overflow, or roll-over above ARR); `u64::MAX` while blocked by ARR = 0.
    pub fn ticks_to_wrap(&self) -> u64 {
        if self.arr_active == 0 {
            u64::MAX
        } else if self.cnt <= self.arr_active {
            (self.arr_active - self.cnt) as u64 + 1
        } else {
            (self.max - self.cnt) as u64 + 1
        }
    }

    /// How many counter ticks until CNT becomes `value` without wrapping first.
    pub fn ticks_to_value(&self, value: u32) -> u64 {
        let limit = if self.cnt <= self.arr_active { self.arr_active } else { self.max };
        if self.arr_active != 0 && value > self.cnt && value <= limit {
            (value - self.cnt) as u64
        } else {
            u64::MAX
        }
    }

    /// CK_PSC pulses before the `k`-th next counter tick (k >= 1): that many pulses are
    /// quiet, the next one produces the tick.
    pub fn pulses_before_tick(&self, k: u64) -> u64 {
        if k == u64::MAX {
            return u64::MAX;
        }
        let period = self.psc_active as u64 + 1;
        ((self.psc_active - self.psc_cnt) as u64).saturating_add((k - 1).saturating_mul(period))
    }

    /// Apply `n` CK_PSC pulses known to contain no wrap (see `ticks_to_wrap`).
    pub fn skip_pulses(&mut self, n: u64) {
        let period = self.psc_active as u64 + 1;
        let total = self.psc_cnt as u64 + n;
        self.psc_cnt = (total % period) as u32;
        if self.arr_active != 0 {
            self.cnt = self.cnt.wrapping_add((total / period) as u32) & self.max;
        }
    }
}
