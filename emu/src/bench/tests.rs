//! The bench mode on its test image, `tests/fixtures/bench-loop.s`: 1000
//! turns of a SUBS/BNE loop that the image also times itself (DWT_CYCCNT).

use super::*;
use std::path::PathBuf;

fn fixture() -> Rc<Image> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/bench-loop.elf");
    Rc::new(crate::image::load_bare(&path).expect("the bench test image loads"))
}

#[test]
fn the_marks_read_the_clocks_where_the_images_own_cycle_counter_does() {
    let o = run(&fixture(), CAP_CYCLES, false).expect("the image reaches bench_done");
    assert_eq!(o.iterations, 1000, "bench_iterations, read from the image");
    assert_eq!(o.acr, 0x0703, "FLASH_ACR as the image wrote it");
    let (model, bound) = o.cycles();
    // DWT_CYCCNT runs on the model's clock: the image's count between its
    // two reads is the model's between the marks (bench_stop is longer than
    // bench_start, so a mark taken at the end of its block would not match)
    assert_eq!(o.ticks, Some(model as u32), "the image counted {:?}, the marks {model}", o.ticks);
    // each turn is a SUBS and a BNE, one cycle each at least (TRM Table 3-1)
    assert!(model >= 2 * 1000, "{model} cycles for 1000 turns");
    assert!(bound >= model, "the bound {bound} under the model {model}");
}

#[test]
fn a_run_that_misses_its_marks_says_which_and_the_cap() {
    let e = run(&fixture(), 1_000, false).expect_err("1000 turns do not fit in 1000 cycles");
    assert!(e.contains("bench_stop, bench_done not reached within 1000 cycles"), "{e}");
    assert!(e.contains("--cap-cycles"), "{e}");
}

#[test]
fn an_image_without_the_protocol_is_refused_by_name() {
    let e = function(&fixture(), "bench_finish").expect_err("no such function");
    assert!(e.contains("`bench_finish`") && e.contains("not a bench image"), "{e}");
}

#[test]
fn a_bad_cap_is_refused_with_its_range() {
    let image = fixture();
    for bad in ["--cap-cycles=abc", "--cap-cycles=5", "--cap-cycles=-1"] {
        assert_eq!(cli(&image, &[bad.to_string()]), 2, "{bad}");
    }
}

#[test]
fn coremark_per_mhz_is_iterations_per_million_cycles() {
    // 3500 iterations in 1.2e9 cycles: 2.9166... per million cycles
    assert_eq!(per_mhz_milli(3500, 1_200_000_000), 2916);
    assert_eq!(per_mhz_milli(1, 0), 1_000_000_000, "no division by zero");
    let o = Outcome {
        iterations: 1000,
        start: (100, 100),
        stop: (3_000_100, 4_000_100),
        ticks: None,
        acr: 0x0703,
        misses: [(0, 0); 2],
        log: String::new(),
        profile: Vec::new(),
    };
    let r = report(&o);
    assert!(r.contains("model   3000000") && r.contains("3000.0") && r.contains("333.333"), "{r}");
    assert!(r.contains("bound   4000000") && r.contains("4000.0") && r.contains("250.000"), "{r}");
}
