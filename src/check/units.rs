//! Units: converting written quantities to metres and degrees, reporting what is missing.

use crate::ast::{Quantity, Unit};
use crate::diag::{Code, Diagnostic, Fix};

/// A fix that rewrites a quantity (number and unit) as `text`.
fn rewrite(q: &Quantity, title: &str, text: String) -> Fix {
    // A number without a unit: its span may run over the blank after it, which the fix keeps.
    let span = if q.unit.is_none() {
        let end = (q.span.start + q.text.len() as u32).min(q.span.end);
        crate::source::Span { end, ..q.span }
    } else {
        q.span
    };
    Fix { title: format!("{title}: `{text}`"), span, replacement: text }
}

/// Converts a length to metres, or reports why it cannot be one. `default` is a unit given for
/// a whole list (`corners in m ...`).
pub(super) fn length_m(
    q: &Quantity,
    default: Option<Unit>,
    what: &str,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<f64> {
    match q.unit.or(default) {
        Some(Unit::M) => Some(q.value),
        Some(Unit::Cm) => Some(q.value / 100.0),
        None => {
            diagnostics.push(
                Diagnostic::new(Code::E0105, format!("{what} `{}` has no unit", q.text))
                    .with_primary(q.span, "a length needs `m` or `cm`")
                    .with_help(format!("add a unit, e.g. `{} m` or `{} cm`", q.text, q.text))
                    .with_fixes([
                        rewrite(q, "add a unit", format!("{} m", q.text)),
                        rewrite(q, "add a unit", format!("{} cm", q.text)),
                    ]),
            );
            None
        }
        Some(unit) => {
            let converted = match unit {
                Unit::Mm => Some(format!("{} cm", crate::ast::format_number(q.value / 10.0))),
                Unit::Ft => Some(format!("{} cm", round2(q.value * 30.48))),
                Unit::In => Some(format!("{} cm", round2(q.value * 2.54))),
                _ => None,
            };
            let help = match &converted {
                Some(text) => format!("write `{text}`"),
                None => "a length is written in `m` or `cm`".to_string(),
            };
            diagnostics.push(
                Diagnostic::new(
                    Code::E0106,
                    format!(
                        "{what} is written in `{}`, which is not a length unit of holoc",
                        unit.as_str()
                    ),
                )
                .with_primary(q.unit_span.unwrap_or(q.span), "expected `m` or `cm`")
                .with_help(help)
                .with_fixes(converted.map(|text| rewrite(q, "convert", text))),
            );
            None
        }
    }
}

/// Converts an angle to degrees in `[0, 360)`, or reports why it cannot be one.
pub(super) fn angle_deg(
    q: &Quantity,
    what: &str,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<f64> {
    let degrees = match q.unit {
        Some(Unit::Deg) => q.value,
        None => {
            diagnostics.push(
                Diagnostic::new(Code::E0105, format!("{what} `{}` has no unit", q.text))
                    .with_primary(q.span, "an angle needs `deg`")
                    .with_help(format!("add the unit: `{} deg`", q.text))
                    .with_fixes([rewrite(q, "add the unit", format!("{} deg", q.text))]),
            );
            return None;
        }
        Some(Unit::Rad) => {
            diagnostics.push(
                Diagnostic::new(Code::E0106, format!("{what} is written in radians"))
                    .with_primary(q.unit_span.unwrap_or(q.span), "expected `deg`")
                    .with_help(format!("write `{} deg`", round2(q.value.to_degrees())))
                    .with_fixes([rewrite(
                        q,
                        "convert",
                        format!("{} deg", round2(q.value.to_degrees())),
                    )]),
            );
            return None;
        }
        Some(unit) => {
            diagnostics.push(
                Diagnostic::new(
                    Code::E0106,
                    format!("{what} is written in `{}`, which is not an angle unit", unit.as_str()),
                )
                .with_primary(q.unit_span.unwrap_or(q.span), "expected `deg`")
                .with_help("an angle is written in `deg`, e.g. `90 deg`"),
            );
            return None;
        }
    };
    Some(degrees.rem_euclid(360.0))
}

/// Reads a whole, unit-less count in `[min, max]`.
pub(super) fn count(
    q: &Quantity,
    what: &str,
    min: u32,
    max: u32,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<u32> {
    if let Some(unit) = q.unit {
        diagnostics.push(
            Diagnostic::new(Code::E0106, format!("{what} takes no unit"))
                .with_primary(q.unit_span.unwrap_or(q.span), format!("remove `{}`", unit.as_str()))
                .with_help(format!("write `{}`", q.text))
                .with_fixes([rewrite(q, "remove the unit", q.text.clone())]),
        );
        return None;
    }
    if q.value.fract() != 0.0 || q.value < f64::from(min) || q.value > f64::from(max) {
        diagnostics.push(
            Diagnostic::new(
                Code::E0208,
                format!("{what} `{}` is not a whole number from {min} to {max}", q.text),
            )
            .with_primary(q.span, format!("expected {min}..={max}")),
        );
        return None;
    }
    Some(q.value as u32)
}

fn round2(value: f64) -> String {
    crate::ast::format_number((value * 100.0).round() / 100.0)
}
