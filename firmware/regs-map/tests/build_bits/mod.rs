//! The tests that compare our bit fields with ST's SVD share this.

/// Build a register value with metapac's setters and return its bits.
macro_rules! bits {
    ($ty:ty, |$r:ident| $set:expr) => {{
        let mut $r = <$ty>::default();
        $set;
        $r.0
    }};
}
