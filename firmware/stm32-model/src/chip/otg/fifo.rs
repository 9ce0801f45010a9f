//! The data FIFOs (§22.11). The RX FIFO (§22.11.1) is shared by all OUT
//! endpoints: each packet is a status word (read with GRXSTSR, popped with
//! GRXSTSP) then its data words, read at any FIFO window. Each IN endpoint has its
//! TX FIFO (§22.11.2). Sizes are checked by the caller against GRXFSIZ/DIEPTXFx.

use crate::unmodelled;
use std::collections::VecDeque;

/// GRXSTSP.PKTSTS in device mode (§22.16.2 GRXSTSR).
pub const OUT_DATA: u32 = 0b0010;
pub const OUT_DONE: u32 = 0b0011;
pub const SETUP_DONE: u32 = 0b0100;
pub const SETUP_DATA: u32 = 0b0110;

/// A GRXSTSR word: EPNUM, BCNT, DPID (DATA0), PKTSTS, FRMNUM.
pub fn status(ep: usize, bcnt: usize, pktsts: u32, frame: u16) -> u32 {
    ep as u32 & 0xF | (bcnt as u32 & 0x7FF) << 4 | pktsts << 17 | (frame as u32 & 0xF) << 21
}

#[derive(Clone, Debug, Default)]
pub struct RxFifo {
    /// (status word, data words) in arrival order
    queue: VecDeque<(u32, Vec<u32>)>,
    /// the data of the entry last popped, not yet read
    popped: VecDeque<u32>,
}

impl RxFifo {
    /// Words held: a status word and the data of each entry.
    pub fn words(&self) -> usize {
        self.queue.iter().map(|e| 1 + e.1.len()).sum::<usize>() + self.popped.len()
    }

    /// True if a status is waiting (GINTSTS.RXFLVL).
    pub fn pending(&self) -> bool {
        !self.queue.is_empty()
    }

    /// Queues a packet if `room` words allow it; false if not (the core NAKs).
    pub fn push(&mut self, status: u32, data: &[u8], room: usize) -> bool {
        let words: Vec<u32> = data.chunks(4).map(word).collect();
        if self.words() + 1 + words.len() > room {
            return false;
        }
        self.queue.push_back((status, words));
        true
    }

    /// The next status word (GRXSTSR), popped with its data readable (GRXSTSP).
    /// Popping before the last packet's data is read, or from an empty FIFO, is
    /// not defined by §22.16.2.
    pub fn status(&mut self, pop: bool) -> u32 {
        if !self.popped.is_empty() {
            unmodelled("OTG_FS GRXSTSR/GRXSTSP before the last packet's data was read");
        }
        let Some(&(s, _)) = self.queue.front() else {
            unmodelled("OTG_FS GRXSTSR/GRXSTSP with the RX FIFO empty (RXFLVL = 0)")
        };
        if pop {
            let (_, data) = self.queue.pop_front().unwrap_or_default();
            self.popped = data.into();
        }
        s
    }

    /// A read at a FIFO window: the next data word of the popped packet.
    pub fn read_data(&mut self) -> u32 {
        self.popped.pop_front().unwrap_or_else(|| unmodelled("OTG_FS RX FIFO read with no packet data popped"))
    }

    pub fn clear(&mut self) {
        self.queue.clear();
        self.popped.clear();
    }
}

fn word(b: &[u8]) -> u32 {
    let mut w = [0u8; 4];
    w[..b.len()].copy_from_slice(b);
    u32::from_le_bytes(w)
}

/// One IN endpoint's TX FIFO, in words as written.
#[derive(Clone, Debug, Default)]
pub struct TxFifo {
    words: VecDeque<u32>,
}

impl TxFifo {
    pub fn words(&self) -> usize {
        self.words.len()
    }

    pub fn push(&mut self, w: u32) {
        self.words.push_back(w);
    }

    /// The next packet of `len` bytes, if the FIFO holds all of it.
    pub fn take(&mut self, len: usize) -> Option<Vec<u8>> {
        let n = len.div_ceil(4);
        if self.words.len() < n {
            return None;
        }
        let mut bytes: Vec<u8> = self.words.drain(..n).flat_map(u32::to_le_bytes).collect();
        bytes.truncate(len);
        Some(bytes)
    }

    pub fn clear(&mut self) {
        self.words.clear();
    }
}
