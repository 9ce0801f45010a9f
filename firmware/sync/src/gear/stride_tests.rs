//! The long-stride path (`advance_many`) lands where the tick's walk does,
//! with the count kept (the property test only checks it back at 0).

use super::*;

#[test]
fn a_long_stride_lands_on_the_walks_steps_and_count() {
    let s = Scale { num: 8, den: 3 };
    for (start, delta) in [(0i64, 1_000i64), (7, -2_501), (-5, 3)] {
        let mut strided = Gear::new(s);
        strided.reset(start);
        strided.advance_many(delta);
        let mut walked = Gear::new(s);
        walked.reset(start);
        walked.advance(delta as i32);
        assert_eq!(strided.count(), start + delta, "{start} + {delta}");
        assert_eq!((strided.steps(), strided.rem2()), (walked.steps(), walked.rem2()), "{start} + {delta}");
        assert_eq!(strided.steps(), s.round(start + delta));
    }
}
