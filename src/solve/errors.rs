//! The solve stage's diagnostics, built in one place.

use super::{HardRule, RoomProblem, Unplaced};
use crate::diag::{Code, Diagnostic};

/// E0501: the outline is not a rectilinear polygon with area.
pub(crate) fn bad_room(problem: &RoomProblem) -> Diagnostic {
    let d = Diagnostic::new(
        Code::E0501,
        format!("room `{}` has an outline the solver cannot use", problem.name),
    )
    .with_help(
        "give at least four corners, walls parallel to the x or z axis, some area, sides up to 100 m",
    )
    .with_note(format!("corners: {:?}", problem.outline));
    match problem.span {
        Some(s) => d.with_primary(s, "this room"),
        None => d,
    }
}

/// E0502 for every object with an unusable size or reference; returns whether all are fine.
pub(crate) fn check_objects(problem: &RoomProblem, diags: &mut Vec<Diagnostic>) -> bool {
    let before = diags.len();
    let good = |v: f64| v.is_finite() && v > 0.0;
    let mut bad = |id: &str, span: Option<crate::source::Span>, what: String| {
        let d = Diagnostic::new(Code::E0502, format!("object `{id}` in room `{}` {what}", problem.name))
            .with_help("give every size as a positive length and refer only to earlier floor objects of the room");
        diags.push(match span {
            Some(s) => d.with_primary(s, "this object"),
            None => d,
        });
    };
    for (k, o) in problem.objects.iter().enumerate() {
        if !(good(o.size[0]) && good(o.size[1]) && good(o.height)) {
            bad(&o.id, o.span, "has a size that is not a positive length".to_string());
        }
        for c in &o.constraints {
            // An implied seating group's seat turns to a screen declared after it (both
            // solvers place the screen first).
            let forward_ok = c.implied && c.target > k && c.target < problem.objects.len();
            if c.target >= k && !forward_ok {
                bad(
                    &o.id,
                    c.span.or(o.span),
                    "has a constraint on itself or on a later object".to_string(),
                );
            }
        }
        if let Some(p) = o.pin {
            if !(p.x.is_finite() && p.z.is_finite()) {
                bad(&o.id, o.span, "has a pinned position that is not finite".to_string());
            }
        }
    }
    for w in &problem.wall_objects {
        if !w.size.iter().all(|v| good(*v)) || w.height_m.is_some_and(|h| !h.is_finite()) {
            bad(&w.id, w.span, "has a size or height that is not a positive length".to_string());
        }
        if w.above.is_some_and(|t| t >= problem.objects.len()) {
            bad(
                &w.id,
                w.span,
                "hangs above an object that is not a floor object of the room".to_string(),
            );
        }
    }
    for s in &problem.small_objects {
        if !s.size.iter().all(|v| good(*v)) {
            bad(&s.id, s.span, "has a size that is not a positive length".to_string());
        }
    }
    if let Some(c) = &problem.ceiling {
        if !c.size.iter().all(|v| good(*v)) || c.above.is_some_and(|t| t >= problem.objects.len()) {
            bad(&c.id, c.span, "has a bad size or hangs over an unknown object".to_string());
        }
    }
    if !(problem.wall_height.is_finite() && problem.wall_height > 0.0) {
        let d = Diagnostic::new(
            Code::E0502,
            format!("room `{}` has a wall height that is not a positive length", problem.name),
        )
        .with_help("give the scene a wall height such as `2.7 m`");
        diags.push(d);
    }
    diags.len() == before
}

/// W0503: an object whose every relation names an object left out is left out too.
pub(crate) fn dependent_left_out(u: &Unplaced, span: Option<crate::source::Span>) -> Diagnostic {
    let d = Diagnostic::new(Code::W0503, format!("`{}` is left out with what it relates to", u.id))
        .with_note(u.reason.clone())
        .with_help("give it a relation to an object that is placed, or make the other object available (an asset, `--catalog`)");
    match span {
        Some(s) => d.with_primary(s, "every relation names an object left out"),
        None => d,
    }
}

/// W0505: a relation is given up because its target is left out; the object keeps its place
/// by its other relations and its room.
pub(crate) fn relation_given_up(
    object: &str,
    relation: &str,
    reason: &str,
    span: crate::source::Span,
) -> Diagnostic {
    Diagnostic::new(
        Code::W0505,
        format!("`{object}` is placed without `{relation}`: {reason}"),
    )
    .with_primary(span, "this relation is given up")
    .with_note("the object is not there for its target, so it stays, placed by its other relations and its room")
    .with_help("make the target available (an asset, `--catalog`), or relate the object to something that is placed")
}

/// The name of a receptacle of the problem.
pub(crate) fn holder_name(problem: &RoomProblem, h: super::Holder) -> &str {
    match h {
        super::Holder::Floor(i) => problem.objects.get(i).map_or("?", |o| o.id.as_str()),
        super::Holder::Wall(i) => problem.wall_objects.get(i).map_or("?", |o| o.id.as_str()),
    }
}

/// W0506: a thing was put on another receptacle of the room than the one declared, because
/// that one may not carry it.
pub(crate) fn moved(problem: &RoomProblem, m: &super::Moved) -> Diagnostic {
    let (from, to) = (m.from, m.to);
    let s = &problem.small_objects[m.small];
    let name = s.id.split('|').next().unwrap_or(&s.id);
    let full: Vec<String> =
        m.full.iter().map(|&h| format!("`{}`", holder_name(problem, h))).collect();
    let pair = match (&s.thor_type, m.p) {
        (Some(t), Some(p)) => {
            format!("; p = {p:.2} for a `{t}` on it in ProcTHOR's receptacle pairs")
        }
        _ => String::new(),
    };
    if let Some(absent) = &m.absent {
        let note = format!(
            "its receptacle `{absent}` is left out: no asset matches it (W0401); `{}` is the nearest receptacle of the room that is a home for it with room for it{}{pair}",
            holder_name(problem, to),
            if full.is_empty() { String::new() } else { format!(" ({} nearer, full or carrying three moved things)", full.join(", ")) }
        );
        let d = Diagnostic::new(
            Code::W0506,
            format!("`{name}` is put on `{}` instead of `{absent}`", holder_name(problem, to)),
        )
        .with_note(note)
        .with_help("give its receptacle an asset (`--catalog`, `--objathor`), or put the thing on a receptacle of the room");
        return match s.span {
            Some(span) => d.with_primary(span, "declared on a receptacle that is left out"),
            None => d,
        };
    }
    let d = Diagnostic::new(
        Code::W0506,
        format!(
            "`{name}` is put on `{}` instead of `{}`",
            holder_name(problem, to),
            holder_name(problem, from)
        ),
    )
    .with_note(if m.full.is_empty() {
        format!(
            "people do not put such a thing on `{}` (the pairs of ProcTHOR's receptacles); `{}` is the nearest receptacle of the room that is a home for it{pair}",
            holder_name(problem, from),
            holder_name(problem, to)
        )
    } else {
        format!(
            "people do not put such a thing on `{}` (the pairs of ProcTHOR's receptacles); `{}` is the nearest receptacle of the room that is a home for it with room for it ({} nearer, full or carrying three moved things){pair}",
            holder_name(problem, from),
            holder_name(problem, to),
            full.join(", ")
        )
    })
    .with_help("put it on top of a receptacle that takes it");
    match s.span {
        Some(span) => d.with_primary(span, "declared on a receptacle that does not take it"),
        None => d,
    }
}

/// Why no pose is left for a floor object, naming every rule that removed poses with how many
/// it removed: the room's fixed rules over the grid of poses (`fixed`: inside the room, the
/// global constraint, door keep-out zones, front clearance, windows), then the rules of the
/// finished layout over the poses those left (`removed`: no overlap, with the objects most in
/// the way, use-clearances, reachability). The rule is the one of the finished layout that
/// removed the most poses.
pub(crate) fn removed_reason<'a>(
    fixed: &std::collections::BTreeMap<HardRule, usize>,
    removed: &[(HardRule, usize)],
    blockers: impl Iterator<Item = (usize, &'a str)>,
) -> (HardRule, String) {
    let mut names: Vec<(usize, &str)> = blockers.collect();
    names.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(b.1)));
    let list: Vec<String> = names.iter().take(3).map(|(_, n)| format!("`{n}`")).collect();
    let tried: usize = removed.iter().map(|(_, n)| n).sum();
    let mut parts: Vec<String> = Vec::new();
    for &(rule, n) in removed.iter().filter(|(_, n)| *n > 0) {
        parts.push(match rule {
            HardRule::NoOverlap if !list.is_empty() => {
                format!("{n} overlap an object already placed ({})", list.join(", "))
            }
            HardRule::NoOverlap => format!("{n} overlap an object already placed"),
            HardRule::UseClearance => {
                format!(
                    "{n} stand in the space another object needs for its use (or block its own)"
                )
            }
            HardRule::Reachable => {
                format!("{n} would leave a placed object (or itself) unreachable from the door")
            }
            other => format!("{n} break {}", other.describe()),
        });
    }
    let fixed: Vec<String> = fixed
        .iter()
        .filter(|(_, n)| **n > 0)
        .map(|(rule, n)| format!("{} {n}", rule.describe()))
        .collect();
    // The rule that removed the most; ties to the later rule of the list (reachability, then
    // use-clearances, then overlap), as a pose is held to them in that order.
    let rule =
        removed.iter().max_by_key(|(_, n)| *n).map_or(HardRule::NoOverlap, |(rule, _)| *rule);
    let before = if fixed.is_empty() {
        String::new()
    } else {
        format!(" (the fixed rules removed: {})", fixed.join(", "))
    };
    (rule, format!("of {tried} poses free of the room's fixed rules, {}{before}", parts.join("; ")))
}

/// W0501: an object was left out.
pub(crate) fn unplaced(problem: &RoomProblem, u: &Unplaced) -> Diagnostic {
    let span = match u.kind {
        "floor" => problem.objects.iter().find(|o| o.id == u.id).and_then(|o| o.span),
        "wall" => problem.wall_objects.iter().find(|o| o.id == u.id).and_then(|o| o.span),
        "small" => problem.small_objects.iter().find(|o| o.id == u.id).and_then(|o| o.span),
        _ => problem.ceiling.as_ref().and_then(|c| c.span),
    };
    if u.code == Code::W0506 {
        // A thing that had to be moved (its receptacle left out or not taking it) and that no
        // receptacle of the room is a home for, or has room for.
        let name = u.id.split('|').next().unwrap_or(&u.id);
        let d = Diagnostic::new(
            Code::W0506,
            format!("`{name}` is left out: no receptacle of room `{}` takes it", problem.name),
        )
        .with_note(u.reason.clone())
        .with_help("put it on top of a receptacle that is a home for it (a table, a shelf, a dresser, a counter), or give its receptacle an asset (`--catalog`, `--objathor`)");
        return match span {
            Some(s) => d.with_primary(s, "left out of the layout"),
            None => d,
        };
    }
    let mut d = Diagnostic::new(
        Code::W0501,
        format!("cannot place {} object `{}` in room `{}`", u.kind, u.id, problem.name),
    )
    .with_note(u.reason.clone());
    d = match span {
        Some(s) => d.with_primary(s, "left out of the layout"),
        None => d,
    };
    if let Some(o) = problem.objects.iter().find(|o| o.id == u.id) {
        for c in &o.constraints {
            if let Some(s) = c.span {
                d = d.with_secondary(s, "constraint of the object left out");
            }
        }
    }
    let help = match u.rule {
        Some(HardRule::InsideRoom) => "choose a smaller object or make the room larger",
        Some(HardRule::Global) => "try the other global constraint (`edge` or `middle`), or a smaller object",
        Some(HardRule::NoOverlap | HardRule::Reachable) => {
            "remove or shrink an earlier object, or declare this object earlier so it is placed first"
        }
        Some(HardRule::UseClearance) => {
            "give it a relation to the object whose space it needs (a chair `in front of` its desk), or free some floor"
        }
        Some(HardRule::DoorKeepOut | HardRule::FrontClearance | HardRule::Window) => {
            "make the object smaller or move a door or window"
        }
        None => "make the object smaller or free some space for it",
    };
    d.with_help(help)
}

/// W0502: a pinned pose breaks a hard rule; it is kept as pinned. A pin that puts the object
/// (partly) outside its room is E0502 instead: the house would not validate (E0607, W0609),
/// and build never writes a house validate rejects.
pub(crate) fn pin_breaks(problem: &RoomProblem, index: usize, rules: &[HardRule]) -> Diagnostic {
    let o = &problem.objects[index];
    if rules.contains(&HardRule::InsideRoom) {
        let d = Diagnostic::new(
            Code::E0502,
            format!("the pinned pose of `{}` puts it outside room `{}`", o.id, problem.name),
        )
        .with_help("move the pin (`at`) inside the room, or remove it to let the solver choose");
        return match o.span {
            Some(s) => d.with_primary(s, "pinned here"),
            None => d,
        };
    }
    let names: Vec<String> = rules.iter().map(|r| format!("`{}`", r.describe())).collect();
    let d = Diagnostic::new(
        Code::W0502,
        match names.len() {
            1 => format!("the pinned pose of `{}` breaks the rule {}", o.id, names[0]),
            _ => format!("the pinned pose of `{}` breaks the rules {}", o.id, names.join(", ")),
        },
    )
    .with_help("move the pin (`at`, `facing`) or remove it to let the solver choose");
    match o.span {
        Some(s) => d.with_primary(s, "pinned here"),
        None => d,
    }
}
