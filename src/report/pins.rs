//! The solved layout as pins (`holoc build --emit layout`): every pose printed with a unit on
//! every number and as many digits as it takes to read back the very same `f64`, so that the
//! statements after an object's id, copied into its block, put it back exactly where the solver
//! put it (a pose rounded to the millimetre could put an object against a wall a fraction of a
//! millimetre into it).
//!
//! A line reads `floor sofa-0 at 0.45525 m, 4.248 m; facing 90 deg  // by dfs`: the statements
//! before `//` are the pins (`at`, `facing` for floor objects; `height` for wall objects, the
//! bottom above the floor, which is what the solver keeps of a wall object's pin), the comment
//! says how it was placed and where (the centre of wall, small and ceiling objects).

use crate::check::scene::Scene;
use crate::solve::Layout;
use std::fmt::Write as _;

/// The shortest decimal text of `v` that reads back as exactly `v` (at most 9 decimals when
/// those are enough, else Rust's shortest round-trip form); `-0` prints as `0`.
pub fn exact_number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v.is_finite() { "0".to_string() } else { format!("{v}") };
    }
    for digits in 0..=9 {
        let text = format!("{v:.digits$}");
        if text.parse::<f64>() == Ok(v) {
            return trim(text);
        }
    }
    format!("{v}")
}

fn trim(text: String) -> String {
    if !text.contains('.') {
        return text;
    }
    let t = text.trim_end_matches('0').trim_end_matches('.');
    t.to_string()
}

fn metres(v: f64) -> String {
    format!("{} m", exact_number(v))
}

/// The layout as pins, room by room (see the module's documentation).
pub fn layout_pins(layout: &Layout, scene: &Scene) -> String {
    let mut out = String::new();
    for solved in &layout.rooms {
        let room = scene.room(solved.room);
        let (ok, total) = solved.layout.constraint_tally(&solved.problem);
        let _ = writeln!(out, "room {} ({ok}/{total} constraints hold)", room.name);
        for placed in &solved.layout.floor {
            let o = &solved.problem.objects[placed.index];
            let failed: Vec<String> = placed
                .constraints
                .iter()
                .filter(|c| !c.measure.satisfied)
                .map(|c| {
                    format!("{} ({} {})", c.text, exact_number(c.measure.value), c.measure.unit)
                })
                .collect();
            let _ = writeln!(
                out,
                "  floor {} at {}, {}; facing {} deg  // by {}{}",
                o.id,
                metres(placed.pose.x),
                metres(placed.pose.z),
                exact_number(placed.pose.rot.deg()),
                placed.by,
                if failed.is_empty() {
                    String::new()
                } else {
                    format!("; violated: {}", failed.join(", "))
                }
            );
        }
        for p in &solved.layout.wall {
            let planned = solved.problem.wall_objects.iter().find(|w| w.id == p.id);
            let h = p.sized_m.or(planned.map(|w| w.size)).map_or(0.0, |s| s[2]);
            // Never below the floor by a rounding error (a `height` under 0 is an error).
            let bottom = (p.position_m[1] - h / 2.0).max(0.0);
            let _ = writeln!(
                out,
                "  wall {} height {}  // centre at {}, {}, {}; facing {} deg",
                p.id,
                metres(bottom),
                metres(p.position_m[0]),
                metres(p.position_m[1]),
                metres(p.position_m[2]),
                exact_number(p.rotation_deg)
            );
        }
        for p in &solved.layout.small {
            let _ = writeln!(
                out,
                "  small {} at {}, {}, {}; facing {} deg",
                p.id,
                metres(p.position_m[0]),
                metres(p.position_m[1]),
                metres(p.position_m[2]),
                exact_number(p.rotation_deg)
            );
        }
        if let Some(c) = &solved.layout.ceiling {
            let _ = writeln!(
                out,
                "  ceiling at {}, {}  // centre height {}",
                metres(c.position_m[0]),
                metres(c.position_m[2]),
                metres(c.position_m[1]),
            );
        }
        for u in &solved.layout.unplaced {
            let _ = writeln!(out, "  not placed: {} {}: {}", u.kind, u.id, u.reason);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::exact_number;

    #[test]
    fn numbers_read_back_as_the_same_f64() {
        for v in [0.45525, 4.248, 0.1 + 0.2, 1.0 / 3.0, 90.0, 2.5e-7, 12_345.678_901_234, -0.0] {
            let text = exact_number(v);
            assert_eq!(text.parse::<f64>().expect("a number"), v, "{text}");
            assert!(!text.contains('e'), "{text}");
        }
        assert_eq!(exact_number(0.45525), "0.45525");
        assert_eq!(exact_number(90.0), "90");
        assert_eq!(exact_number(-0.0), "0");
        assert_eq!(exact_number(0.1 + 0.2), "0.30000000000000004");
    }
}
