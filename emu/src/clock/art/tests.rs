use super::*;

/// FLASH_ACR as the firmware leaves it at 96 MHz: 3 wait states, prefetch and
/// both caches on (0x0703, RM0383 §3.4.1 Table 5 at 2.7-3.6 V).
const FIRMWARE_ACR: u32 = 0x0703;

fn art(bound: bool) -> Art {
    let mut a = if bound { Art::bound() } else { Art::model() };
    a.acr = Acr::from_reg(FIRMWARE_ACR);
    a
}

#[test]
fn the_firmwares_acr_reads_as_three_wait_states_with_everything_on() {
    let acr = Acr::from_reg(FIRMWARE_ACR);
    assert_eq!(acr, Acr { latency: 3, prefetch: true, icache: true, dcache: true });
    assert_eq!(acr.read_len(), 4);
}

#[test]
fn a_miss_costs_the_wait_states_and_a_second_fetch_of_the_line_nothing() {
    let mut a = art(false);
    assert_eq!(a.fetch(100, 0), 3, "at least the wait states (§3.4.2)");
    assert_eq!(a.fetch(100, 1), 0, "the line in use");
}

#[test]
fn sequential_code_runs_from_the_prefetched_line_without_waiting() {
    let mut a = art(false);
    // 100's read holds the flash for cycles 0-3; 101's prefetch follows, ready at 7
    a.fetch(100, 0);
    assert_eq!(a.fetch(101, 8), 0, "four cycles or more on a line hide the next read");
    assert_eq!(a.fetch(102, 9), 2, "one cycle on 101: its prefetch of 102 (from 8) is not ready");
}

#[test]
fn a_branch_target_read_once_hits_the_instruction_cache_after() {
    let mut a = art(false);
    a.fetch(100, 0);
    a.fetch(200, 20);
    assert_eq!(a.fetch(100, 40), 0, "copied into the cache on its miss");
    assert_eq!(a.misses.0, 2);
}

#[test]
fn lines_reached_through_the_prefetch_are_not_copied_into_the_cache() {
    let mut a = art(false);
    a.fetch(100, 0);
    a.fetch(101, 10); // from the prefetch: not a miss
    a.fetch(300, 20);
    assert_eq!(a.fetch(101, 40), 3, "only a miss is copied in (§3.4.2)");
}

#[test]
fn the_least_recently_used_of_64_lines_is_the_one_replaced() {
    let mut a = art(false);
    a.acr.prefetch = false;
    for (i, l) in (1000..1064).enumerate() {
        a.fetch(l, 10 * i as u64);
    }
    a.fetch(1000, 700); // 1000 used again: 1001 is now the oldest
    a.fetch(2000, 710); // a 65th line replaces 1001
    assert_eq!(a.fetch(1000, 720), 0);
    assert_eq!(a.fetch(1001, 730), 3);
}

#[test]
fn a_literal_misses_once_then_comes_from_the_data_cache() {
    let mut a = art(false);
    assert_eq!(a.literal(500, 0), 3);
    assert_eq!(a.literal(500, 10), 0);
    assert_eq!(a.misses.1, 1);
}

#[test]
fn a_literal_waits_for_a_prefetch_under_way() {
    let mut a = art(false);
    a.fetch(100, 0); // the prefetch of 101 holds the flash for cycles 4-7
    assert_eq!(a.literal(500, 4), 4 + 3, "the read under way ends first (at 8)");
}

#[test]
fn the_bound_waits_out_a_whole_read_before_each_miss() {
    let mut a = art(true);
    assert_eq!(a.fetch(100, 0), 4 + 3, "2 x LATENCY + 1");
    assert_eq!(a.literal(900, 20), 7);
}

#[test]
fn a_flushed_cache_is_cold() {
    let mut a = art(true);
    a.fetch(100, 0);
    a.fetch(200, 20);
    a.flush();
    assert_eq!(a.fetch(100, 40), 7);
}

#[test]
fn without_wait_states_nothing_stalls() {
    let mut a = Art::model();
    a.acr = Acr::from_reg(0);
    assert_eq!(a.fetch(1, 0), 0);
    assert_eq!(a.fetch(7, 1), 0);
    assert_eq!(a.literal(9, 2), 0);
}
