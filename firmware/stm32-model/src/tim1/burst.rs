//! TIM1's update DMA request and DMA burst through TIMx_DMAR (RM0383 §12.4.19-20).

use super::Tim1;
use crate::addr::off;
use crate::bits::dcr;
use crate::unmodelled;

impl Tim1 {
    /// Update DMA request (UDE, §12.4.4). One raised while the previous one is still
    /// pending merges with it on the request line and is counted as an overrun.
    pub(super) fn raise_dma_request(&mut self) {
        if self.dma_req {
            self.dma_overruns += 1;
        } else {
            self.dma_req = true;
        }
    }

    /// The DMA controller could not take the request (stream disabled): it is lost, and
    /// the burst index restarts (the manual does not say what the index does then).
    pub fn drop_dma_request(&mut self) {
        self.dma_req = false;
        self.burst_idx = 0;
    }

    /// A DMA transfer wrote `value` at register offset `off`. The DMA acknowledge
    /// releases the request (§9.3.2 "DMA transactions") before the write lands; through
    /// DMAR the timer keeps requesting until the (DBL+1)-th access (§12.4.19-20).
    pub fn dma_write(&mut self, off: u32, value: u32) {
        let target = if off == off::DMAR {
            let (target, last) = self.dmar_target();
            if last {
                self.dma_req = false;
            }
            target
        } else {
            self.dma_req = false;
            off
        };
        self.write(target, value);
    }

    /// The register a TIMx_DMAR access reaches: "(TIMx_CR1 address) + (DBA + DMA index)
    /// x 4 ... DMA index ... ranges from 0 to DBL" (§12.4.20 DMAR). Advances the index;
    /// the second value tells whether this was the burst's last access.
    pub(super) fn dmar_target(&mut self) -> (u32, bool) {
        let dbl = dcr::DBL.get(self.dcr);
        let target = (dcr::DBA.get(self.dcr) + self.burst_idx) * 4;
        let last = self.burst_idx >= dbl;
        self.burst_idx = if last { 0 } else { self.burst_idx + 1 };
        if target >= off::DMAR {
            let a = crate::addr::TIM1 + target;
            unmodelled(&format!("TIM1_DMAR (DBA + index) reaching {a:#010x}, at or past DMAR itself"));
        }
        (target, last)
    }
}
