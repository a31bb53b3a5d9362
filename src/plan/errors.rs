//! Number formatting shared by the plan stage's diagnostics and dump.

use crate::geometry::Point;

/// A length in metres as diagnostics print it: at most two decimals, no trailing zeros.
pub(crate) fn m(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_owned()
    } else {
        s.to_owned()
    }
}

/// A point as diagnostics print it: `(x m, z m)`.
pub(crate) fn pt(p: Point) -> String {
    format!("({} m, {} m)", m(p[0]), m(p[1]))
}
